#include "report/lot_report.h"

#include <map>

#include "core/error.h"
#include "core/format.h"

namespace gyrosid {
namespace {

// A CSV field: quoted, its quotes doubled (RFC 4180).
std::string csv_field(const std::string& text) {
  std::string q = "\"";
  for (char ch : text) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

}  // namespace

std::vector<std::filesystem::path> screen_dirs(const std::filesystem::path& out, const std::vector<std::string>& recordings) {
  if (recordings.size() == 1) return {out};
  std::vector<std::filesystem::path> paths;
  for (const auto& r : recordings) paths.push_back(std::filesystem::absolute(r).lexically_normal());
  std::filesystem::path common = paths.front().parent_path();
  for (const auto& p : paths) {
    while (!common.empty() && p.lexically_relative(common).begin()->string() == "..") common = common.parent_path();
  }
  std::vector<std::filesystem::path> dirs;
  std::map<std::filesystem::path, std::string> seen;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    std::filesystem::path name = paths[k].lexically_relative(common);
    name.replace_extension();
    if (auto [it, fresh] = seen.emplace(name, recordings[k]); !fresh) {
      fail("--recording ", it->second, " and ", recordings[k], " would both be screened into ", (out / name).string());
    }
    dirs.push_back(out / name);
  }
  return dirs;
}

nlohmann::json screen_json(const ScreenResult& result, const std::string& recording, const std::string& prior, double alpha,
                           double white_dph_at_1hz) {
  nlohmann::json j = result.to_json();
  j["recording"] = recording;
  j["prior"] = prior;
  j["alpha"] = alpha;
  j["white_dph_at_1hz"] = white_dph_at_1hz;
  return j;
}

std::string screens_csv_row(const ScreenResult& r, const std::string& recording, double white_dph_at_1hz) {
  return str_cat(csv_field(recording), ",", r.out_of_family ? "true" : "false", ",", format_number(r.p_value), ",", format_number(r.p_physics), ",",
                 format_number(r.p_noise), ",", format_number(white_dph_at_1hz), ",", csv_field(r.reasons.empty() ? "" : r.reasons.front()), "\n");
}

}  // namespace gyrosid
