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

// One subcommand's registration: its options and help added to the app, and the action it sets when chosen.
using Verb = void(CLI::App& app, Action& action);
// The built-in subcommands, one cmd_<name>.cpp each.
Verb register_simulate, register_allan, register_run, register_calibrate, register_compensate, register_export, register_surface,
    register_cof, register_explain, register_design, register_import, register_session, register_lot;

using VerbRegistration = Verb*;
// Every subcommand of `gyrosid`, in the order --help lists them: the thirteen above. A program built on
// gyrosid_cli adds its own before it calls main (not thread-safe); tests/cli/toy_verb.cpp adds one.
std::vector<VerbRegistration>& extend_verbs();

}  // namespace gyrosid::cli
