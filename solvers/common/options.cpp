#include "solvers/common/options.h"

#include <cstdlib>
#include <sstream>

#include "core/error.h"
#include "core/format.h"

namespace gyrosid {

std::pair<std::string, std::string> split_option(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) fail("option '", text, "' is not of the form key=value");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

OptionMap parse_options(const std::vector<std::string>& texts) {
  OptionMap map;
  for (const auto& text : texts) {
    auto [key, value] = split_option(text);
    map[key] = std::move(value);
  }
  return map;
}

OptionTable& OptionTable::real(const std::string& key, double* field, double min, double max, std::string help, bool min_open) {
  const std::string range = str_cat(min_open ? "(" : "[", format_number(min), ", ", format_number(max), "]");
  entries_.push_back({key, std::move(help), range,
                      [=, this](const std::string& v) {
                        char* end = nullptr;
                        const double x = std::strtod(v.c_str(), &end);
                        if (v.empty() || *end != '\0') fail(owner_, " option '", key, "' = '", v, "' is not a number");
                        if (!(min_open ? x > min : x >= min) || !(x <= max)) {
                          fail(owner_, " option '", key, "' = ", v, " is outside its range ", range);
                        }
                        *field = x;
                      },
                      [=] { return format_number(*field); }});
  return *this;
}

OptionTable& OptionTable::integer(const std::string& key, int* field, int min, int max, std::string help) {
  const std::string range = str_cat("[", min, ", ", max, "]");
  entries_.push_back({key, std::move(help), range,
                      [=, this](const std::string& v) {
                        char* end = nullptr;
                        const long x = std::strtol(v.c_str(), &end, 10);
                        if (v.empty() || *end != '\0') fail(owner_, " option '", key, "' = '", v, "' is not an integer");
                        if (x < min || x > max) fail(owner_, " option '", key, "' = ", v, " is outside its range ", range);
                        *field = static_cast<int>(x);
                      },
                      [=] { return std::to_string(*field); }});
  return *this;
}

OptionTable& OptionTable::flag(const std::string& key, bool* field, std::string help) {
  entries_.push_back({key, std::move(help), "true|false",
                      [=, this](const std::string& v) {
                        if (v == "true" || v == "1" || v == "yes") *field = true;
                        else if (v == "false" || v == "0" || v == "no") *field = false;
                        else fail(owner_, " option '", key, "' = '", v, "' must be true or false");
                      },
                      [=] { return std::string(*field ? "true" : "false"); }});
  return *this;
}

OptionTable& OptionTable::choice(const std::string& key, std::string* field, std::vector<std::string> allowed, std::string help) {
  std::string range;
  for (const auto& a : allowed) range += (range.empty() ? "" : "|") + a;
  entries_.push_back({key, std::move(help), range,
                      [=, this](const std::string& v) {
                        for (const auto& a : allowed)
                          if (a == v) {
                            *field = v;
                            return;
                          }
                        fail(owner_, " option '", key, "' = '", v, "'; allowed: ", range);
                      },
                      [=] { return *field; }});
  return *this;
}

OptionTable& OptionTable::text(const std::string& key, std::string* field, std::string help) {
  entries_.push_back({key, std::move(help), "text", [=](const std::string& v) { *field = v; }, [=] { return *field; }});
  return *this;
}

OptionTable& OptionTable::passthrough(const std::string& prefix, OptionMap* field, std::string help) {
  passthroughs_.push_back({prefix, std::move(help), field});
  return *this;
}

void OptionTable::apply(const OptionMap& options) const {
  for (const auto& [key, value] : options) {
    bool found = false;
    for (const auto& p : passthroughs_) {
      if (key.size() > p.prefix.size() && key.rfind(p.prefix, 0) == 0) {
        (*p.field)[key.substr(p.prefix.size())] = value;
        found = true;
      }
    }
    if (found) continue;
    for (const auto& e : entries_) {
      if (e.key == key) {
        e.set(value);
        found = true;
      }
    }
    if (!found) {
      std::string keys;
      for (const auto& e : entries_) keys += (keys.empty() ? "" : ", ") + e.key;
      for (const auto& p : passthroughs_) keys += ", " + p.prefix + "<key>";
      fail(owner_, ": unknown option '", key, "'; known: ", keys);
    }
  }
}

std::string OptionTable::help() const {
  std::ostringstream out;
  for (const auto& e : entries_) out << "    " << e.key << "=" << e.current() << "  " << e.range << "  " << e.help << "\n";
  for (const auto& p : passthroughs_) out << "    " << p.prefix << "<key>=<value>  " << p.help << "\n";
  return out.str();
}

}  // namespace gyrosid
