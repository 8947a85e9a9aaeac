// The `gyrosid` command: subcommands parse their options, build the library's options structs, call the
// library and report. Each subcommand lives in its own cmd_*.cpp and registers itself here.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <vector>

namespace gyrosid::cli {

int main(int argc, char** argv);

// A subcommand's action runs after parsing; Errors thrown from it are reported as "gyrosid <cmd>: error: ..."
// with exit status 2.
using Action = std::function<void()>;

void register_simulate(CLI::App& app, Action& action);
void register_allan(CLI::App& app, Action& action);
void register_run(CLI::App& app, Action& action);
void register_calibrate(CLI::App& app, Action& action);
void register_compensate(CLI::App& app, Action& action);
void register_export(CLI::App& app, Action& action);
void register_surface(CLI::App& app, Action& action);
void register_cof(CLI::App& app, Action& action);
void register_explain(CLI::App& app, Action& action);
void register_design(CLI::App& app, Action& action);
void register_import(CLI::App& app, Action& action);
void register_session(CLI::App& app, Action& action);
void register_lot(CLI::App& app, Action& action);

// Adds one subcommand to the app: its options and help, and the action it sets when it is chosen.
using VerbRegistration = void (*)(CLI::App& app, Action& action);
// Every subcommand of `gyrosid`, in the order --help lists them: the thirteen above. A program built on
// gyrosid_cli adds its own before it calls main (not thread-safe); tests/cli/toy_verb.cpp adds one.
std::vector<VerbRegistration>& extend_verbs();

}  // namespace gyrosid::cli
