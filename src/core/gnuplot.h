// Plots are rendered by gnuplot (Debian package gnuplot-nox) into PNG files, atomically. Callers write
// the plot commands and inline data blocks; this sets the pngcairo terminal and the output.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace gyrosid {

struct PngSize {
  int width = 960;
  int height = 640;
};

// Runs gnuplot on `script` (which must not set terminal or output) and moves the image to `png`.
// An Error carries gnuplot's own message when the script fails.
void render_png(const std::filesystem::path& png, const std::string& script, PngSize size = {});

// An inline gnuplot data block: "$name << EOD\n<rows>\nEOD\n". Each row is whitespace-separated numbers;
// an empty row separates blocks (for pm3d grids and line breaks).
std::string datablock(std::string_view name, const std::vector<std::vector<double>>& rows);

// Quotes a label for gnuplot (single quotes, embedded quotes escaped).
std::string gnuplot_quote(std::string_view text);

}  // namespace gyrosid
