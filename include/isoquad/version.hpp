#pragma once

namespace isoquad {
// The library version, "MAJOR.MINOR.PATCH".
const char* version();
}  // namespace isoquad
