#include "cli/app.h"

#include <cstdio>
#include <iostream>

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"

namespace gyrosid::cli {

std::vector<VerbRegistration>& extend_verbs() {
  static std::vector<VerbRegistration> verbs{register_run,    register_simulate, register_allan,  register_calibrate, register_compensate,
                                             register_surface, register_export,  register_cof,    register_explain,   register_design,
                                             register_import,  register_session, register_lot};
  return verbs;
}

int main(int argc, char** argv) {
  CLI::App app{
      "gyrosid - gyroscope calibration as system identification.\n"
      "Simulate a gyro along rate-table/chamber trajectories, analyse its noise, fit calibration models,\n"
      "score them by strapdown-INS position error and find the physics a simulation left out.\n"
      "Every subcommand has --help. Configs may be files or built-in copies (builtin:sensors/...)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "gyrosid 0.1.0");
  bool quiet = false;
  int threads = 0;
  app.add_flag("--quiet", quiet, "No progress lines on stderr (the environment variable GYROSID_QUIET=1 does the same)");
  app.add_option("--threads", threads, "Worker threads (default: GYROSID_THREADS, else every core); results do not depend on it")
      ->check(CLI::Range(1, 1024));
  app.footer("Environment: GYROSID_QUIET=1 silences progress and GYROSID_THREADS=n sets the worker threads (the options\n"
             "--quiet and --threads, before the subcommand, override both); GYROSID_GNUPLOT names the gnuplot executable\n"
             "(default: gnuplot on PATH). Nothing else is read from the environment.");
  Action action;
  for (const VerbRegistration add : extend_verbs()) add(app, action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (quiet) set_quiet_progress(true);
  if (threads > 0) set_worker_threads(threads);
  try {
    action();
  } catch (const Error& e) {
    const auto subs = app.get_subcommands();
    std::fprintf(stderr, "gyrosid %s: error: %s\n", subs.empty() ? "" : subs.front()->get_name().c_str(), e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gyrosid: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}

}  // namespace gyrosid::cli
