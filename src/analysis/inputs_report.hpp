#pragma once
// What the diagnosis made of each recording's channels: compared, or not (not recorded, a set point),
// resolution and noise floor, and what reading the file did (rows skipped, gaps). For diagnosis.json
// ("inputs") and report.md.
#include <string>
#include <vector>

#include "analysis/comparison.hpp"

namespace analysis {

std::string inputs_json(const std::vector<const Dataset*>& datasets);
std::string inputs_markdown(const std::vector<const Dataset*>& datasets);

}  // namespace analysis
