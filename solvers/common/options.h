// key=value options for solvers (`gyrosid calibrate --set key=value`). Each solver's options struct binds
// its fields in a table with ranges and a one-line description; unknown keys and out-of-range values are
// errors that name the option and its allowed values or range.
#pragma once

#include <functional>
#include <limits>
#include <map>
#include <string>
#include <memory>
#include <vector>

#include "core/error.h"
#include "core/registry.h"

namespace gyrosid {

using OptionMap = std::map<std::string, std::string>;

class OptionTable {
 public:
  explicit OptionTable(std::string owner) : owner_(std::move(owner)) {}

  OptionTable& real(const std::string& key, double* field, double min, double max, std::string help,
                    bool min_open = false);
  OptionTable& integer(const std::string& key, int* field, int min, int max, std::string help);
  OptionTable& flag(const std::string& key, bool* field, std::string help);
  OptionTable& choice(const std::string& key, std::string* field, std::vector<std::string> allowed, std::string help);
  OptionTable& text(const std::string& key, std::string* field, std::string help);
  // Keys "<prefix><key>" are collected, prefix stripped, into `field` for another component (e.g. the
  // options of the solver that starts this one: "init.width=0.3").
  OptionTable& passthrough(const std::string& prefix, OptionMap* field, std::string help);

  // Applies every entry; an unknown key is an Error listing the known ones.
  void apply(const OptionMap& options) const;
  std::string help() const;  // one line per option: key, default/range, description

 private:
  struct Entry {
    std::string key, help, range;
    std::function<void(const std::string&)> set;
    std::function<std::string()> current;
  };
  std::string owner_;
  std::vector<Entry> entries_;
  struct Passthrough {
    std::string prefix, help;
    OptionMap* field;
  };
  std::vector<Passthrough> passthroughs_;
};

// Base of a family member (an RBF solver, a least-squares back-end, a design solver) whose options struct O
// has defaults, table() and validate(): what options_entry<Base, S> needs.
template <typename Base, typename O>
class WithOptions : public Base {
 public:
  using Options = O;
  explicit WithOptions(Options options) : o_(std::move(options)) {}

 protected:
  Options o_;
};

// A registry entry for a class S of family Base with `using Options = ...;` (defaults, table(), validate())
// and a constructor S(Options, extra...): its help lists the options with their defaults and ranges; the
// options are applied and validated when S is made, errors prefixed by `owner` and the name.
template <typename Base, typename S, typename... Extra>
typename Registry<Base, const OptionMap&, Extra...>::Entry options_entry(std::string name, std::string summary, std::string owner) {
  return {name, summary,
          [name, summary] {
            typename S::Options o;
            return name + " - " + summary + ":\n" + o.table().help();
          },
          [name, owner](const OptionMap& map, Extra... extra) -> std::unique_ptr<Base> {
            typename S::Options o;
            o.table().apply(map);
            if (const std::string problem = o.validate(); !problem.empty()) fail(owner, name, ": ", problem);
            return std::make_unique<S>(std::move(o), extra...);
          }};
}

// "key=value" -> {key, value}; Error naming the text when there is no '='.
std::pair<std::string, std::string> split_option(const std::string& text);
// `--set`'s "key=value" texts as a map (a later key replaces an earlier one); Error as split_option.
OptionMap parse_options(const std::vector<std::string>& texts);

}  // namespace gyrosid
