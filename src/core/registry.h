// One registry per pluggable family (RBF solvers, model kinds, explain effects, design solvers): a name,
// a one-line summary, a help text and a factory, listed in one place. An unknown name is an Error that
// lists the known ones. Entries are added explicitly by the family's own registration function (no static
// self-registration: a static library would drop unreferenced entries).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"

namespace gyrosid {

template <typename Product, typename... Args>
class Registry {
 public:
  struct Entry {
    std::string name;
    std::string summary;                                  // one line, for listings
    std::function<std::string()> help;                    // the options with defaults, ranges and meanings
    std::function<std::unique_ptr<Product>(Args...)> make;
  };

  explicit Registry(std::string noun) : noun_(std::move(noun)) {}

  Registry& add(Entry entry) {
    for (const auto& e : entries_) {
      if (e.name == entry.name) fail(noun_, " '", entry.name, "' registered twice");
    }
    entries_.push_back(std::move(entry));
    return *this;
  }

  const Entry* find(std::string_view name) const {
    for (const auto& e : entries_) {
      if (e.name == name) return &e;
    }
    return nullptr;
  }
  const Entry& at(std::string_view name) const {
    if (const Entry* e = find(name)) return *e;
    fail("unknown ", noun_, " '", name, "'; known: ", known());
  }
  std::unique_ptr<Product> make(std::string_view name, Args... args) const { return at(name).make(std::forward<Args>(args)...); }

  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& e : entries_) out.push_back(e.name);
    return out;
  }
  std::string known() const {
    std::string out;
    for (const auto& e : entries_) out += (out.empty() ? "" : ", ") + e.name;
    return out;
  }
  const std::vector<Entry>& entries() const { return entries_; }
  const std::string& noun() const { return noun_; }

 private:
  std::string noun_;
  std::vector<Entry> entries_;
};

}  // namespace gyrosid
