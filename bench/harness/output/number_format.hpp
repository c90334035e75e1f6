// How the output files write a number: CSV, Markdown tables and JSON each have one way, so that
// one quantity reads the same in every file and table that holds it.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace chainmail {

// the number formatting every CSV uses (empty for NaN and inf: an absent or failed metric)
std::string csv_number(double value);
// a number for a Markdown table: `significant` digits, "-" for NaN and inf
std::string table_number(double value, int significant);
// a number for JSON: null when not finite
nlohmann::json json_number(double value);

}  // namespace chainmail
