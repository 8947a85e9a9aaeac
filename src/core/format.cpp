#include "core/format.h"

#include <locale.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace gyrosid {

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string format_significant(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

double parse_c_double(const char* begin, char** end) {
  static locale_t c_locale = newlocale(LC_ALL_MASK, "C", locale_t(0));
  return strtod_l(begin, end, c_locale);
}

std::string join(const std::vector<std::string>& items, std::string_view separator) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) (out += i ? separator : std::string_view{}) += items[i];
  return out;
}

std::string join(const std::vector<std::string>& items, std::string_view separator, std::string_view last) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) (out += i == 0 ? std::string_view{} : i + 1 == items.size() ? last : separator) += items[i];
  return out;
}

std::string format_numbers(const std::vector<double>& values, std::string_view separator) {
  std::vector<std::string> items;
  items.reserve(values.size());
  for (double v : values) items.push_back(format_number(v));
  return join(items, separator);
}

std::vector<std::string> split_list(const std::string& text, char separator) {
  std::vector<std::string> out;
  for (std::size_t a = 0, b; a <= text.size(); a = b + 1) {
    b = std::min(text.find(separator, a), text.size());
    std::size_t first = a, last = b;  // the item without the blanks around it
    while (first < last && text[first] == ' ') ++first;
    while (last > first && text[last - 1] == ' ') --last;
    if (last > first) out.push_back(text.substr(first, last - first));
  }
  return out;
}

}  // namespace gyrosid
