// JSON forms of the reports (nlohmann::json, forward-declared so that this header stays light).
#pragma once

#include <nlohmann/json_fwd.hpp>

#include "prep/prepare.hpp"

namespace isoquad {

void to_json(nlohmann::json& j, const InputReport& report);
void to_json(nlohmann::json& j, const ComponentReport& report);

}  // namespace isoquad
