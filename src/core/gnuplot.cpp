#include "core/gnuplot.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/format.h"
#include "core/error.h"

namespace gyrosid {

std::string gnuplot_quote(std::string_view text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') out += "''";
    else out += c;
  }
  return out + "'";
}

std::string datablock(std::string_view name, const std::vector<std::vector<double>>& rows) {
  std::string out = str_cat("$", name, " << EOD\n");
  for (const auto& row : rows) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i) out += ' ';
      out += format_number(row[i]);
    }
    out += '\n';
  }
  return out + "EOD\n";
}

void render_png(const std::filesystem::path& png, const std::string& script, PngSize size) {
  if (png.has_parent_path()) std::filesystem::create_directories(png.parent_path());
  const std::filesystem::path tmp_png = temporary_sibling(png);
  const std::filesystem::path tmp_script = temporary_sibling(png.parent_path() / "plot.gp");
  const std::filesystem::path tmp_err = temporary_sibling(png.parent_path() / "plot.err");
  auto cleanup = [&] {
    std::error_code ec;
    std::filesystem::remove(tmp_png, ec);
    std::filesystem::remove(tmp_script, ec);
    std::filesystem::remove(tmp_err, ec);
  };
  {
    std::ofstream out(tmp_script);
    out << "set terminal pngcairo noenhanced size " << size.width << "," << size.height
        << " font 'Sans,10'\n"
        << "set output " << gnuplot_quote(tmp_png.string()) << "\n"
        << script << "\nset output\n";
  }
  const char* exe = std::getenv("GYROSID_GNUPLOT");
  const std::string command = str_cat(exe ? exe : "gnuplot", " ", gnuplot_quote(tmp_script.string()), " 2> ",
                                      gnuplot_quote(tmp_err.string()));
  const int status = std::system(command.c_str());
  if (status != 0) {
    std::ifstream err(tmp_err);
    std::stringstream message;
    message << err.rdbuf();
    cleanup();
    fail(png.string(), ": gnuplot failed (is the Debian package gnuplot-nox installed?): ", message.str());
  }
  std::error_code ec;
  std::filesystem::rename(tmp_png, png, ec);
  cleanup();
  if (ec) fail(png.string(), ": cannot move plot into place: ", ec.message());
}

}  // namespace gyrosid
