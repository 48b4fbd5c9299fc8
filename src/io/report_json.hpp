// JSON forms of the reports (nlohmann::json, forward-declared so that this header stays light).
#pragma once

#include <nlohmann/json_fwd.hpp>

#include "metrics/quality.hpp"
#include "prep/prepare.hpp"

namespace isoquad {

void to_json(nlohmann::json& j, const InputIssue& issue);
void to_json(nlohmann::json& j, const InputReport& report);
void to_json(nlohmann::json& j, const ComponentReport& report);
void to_json(nlohmann::json& j, const Topology& t);
void to_json(nlohmann::json& j, const QualityReport& report);

}  // namespace isoquad
