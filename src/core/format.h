// Number formatting for files and reports.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace gyrosid {

// Shortest text that reads back to the same double ("0.1", "-15", "1e-07"); "nan", "inf", "-inf".
// Used for every number written to a data file, so files round-trip bit for bit.
std::string format_number(double value);

// For humans (reports, console): `digits` significant digits, no trailing zeros ("0.1666", "1.2e-05").
std::string format_significant(double value, int digits = 4);

// The items with `separator` between them ("a, b, c").
std::string join(const std::vector<std::string>& items, std::string_view separator = ", ");
// The same with `last` before the final item ("a, b or c"), for lists in help text.
std::string join(const std::vector<std::string>& items, std::string_view separator, std::string_view last);
// The numbers, each as format_number writes it, with `separator` between them ("-20, 0, 1e-07").
std::string format_numbers(const std::vector<double>& values, std::string_view separator = ", ");

// The non-empty items of `text` between `separator`s, without the blanks around them ("short,, long" ->
// {"short", "long"}): join's inverse.
std::vector<std::string> split_list(const std::string& text, char separator = ',');

// strtod in the C locale whatever the process locale is (recordings, flight CSVs: "numbers in C locale").
double parse_c_double(const char* begin, char** end);

}  // namespace gyrosid
