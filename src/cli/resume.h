// Kill-safe, resumable subcommands (cof --monte-carlo, design, explain): what a run's checkpoint is a
// checkpoint of (where it lives: checkpoint_in, core/checkpoint.h).
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "core/checkpoint.h"

namespace gyrosid::cli {

// The fingerprint of a run: every option of the subcommand as given or defaulted (but --resume and --out),
// and the contents of the files named in `files` (a name that is no readable file, such as a built-in flight,
// counts as itself). A resume with any other input is refused.
std::string run_fingerprint(const CLI::App& command, const std::vector<std::string>& files);

}  // namespace gyrosid::cli
