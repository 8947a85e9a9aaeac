#include "core/progress.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace gyrosid {

namespace {
int quiet_override = -1;  // -1: from the environment
thread_local int silenced_here = 0;  // ProgressSilenced guards alive on this thread

bool progress_quiet() {
  if (silenced_here > 0) return true;
  const char* quiet = std::getenv("GYROSID_QUIET");
  return quiet_override >= 0 ? quiet_override == 1 : quiet != nullptr && std::string_view(quiet) != "0";
}

}  // namespace

void set_quiet_progress(bool quiet) { quiet_override = quiet ? 1 : 0; }

ProgressSilenced::ProgressSilenced() { ++silenced_here; }
ProgressSilenced::~ProgressSilenced() { --silenced_here; }

void progress_note(std::string_view text) {
  if (progress_quiet()) return;
  std::fprintf(stderr, "%.*s\n", static_cast<int>(text.size()), text.data());
  std::fflush(stderr);
}

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total == 0 ? 1 : total),
      start_(std::chrono::steady_clock::now()), last_print_(start_) {
  tty_ = ::isatty(STDERR_FILENO) != 0;
  quiet_ = progress_quiet();
}

Progress::~Progress() { finish(); }

void Progress::update(std::size_t done) {
  if (quiet_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (elapsed < 1.0) return;
  const double fraction = static_cast<double>(done) / static_cast<double>(total_);
  const int decile = static_cast<int>(fraction * 10.0);
  if (tty_) {
    if (std::chrono::duration<double>(now - last_print_).count() < 0.5) return;
  } else if (decile == last_decile_) {
    return;
  }
  last_print_ = now;
  last_decile_ = decile;
  const double remaining = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  std::fprintf(stderr, "%s%s: %5.1f %%  %6.1f s elapsed, ~%.0f s left%s", tty_ ? "\r" : "", label_.c_str(),
               100.0 * fraction, elapsed, remaining, tty_ ? "   " : "\n");
  std::fflush(stderr);
  printed_ = true;
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (quiet_ || !printed_) return;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::fprintf(stderr, "%s%s: done in %.1f s%s\n", tty_ ? "\r" : "", label_.c_str(), elapsed,
               tty_ ? "                         " : "");
}

}  // namespace gyrosid
