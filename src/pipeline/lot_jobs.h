// `gyrosid lot learn` and `gyrosid lot screen` as library jobs (issue 33): the CLI and Python parse their
// options into these structs and call the same functions, which compute (lot/), write through lot_report.h
// and keep a checkpoint, so a killed run - started by either - resumes to the same bytes.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "lot/lot_members.h"
#include "lot/lot_model.h"
#include "lot/screen.h"
#include "solvers/calibrate.h"
#include "solvers/common/options.h"

namespace gyrosid {

struct LotLearnOptions {
  std::vector<std::string> recordings;         // each unit's recording, calibrated here with the grey-box model
  std::vector<std::string> models;             // or each unit's calibrated grey-box model file
  std::vector<std::string> screen_recordings;  // the same units on the screening programme (optional, same order)
  OptionMap structure;                         // grey-box options of the units' structure (recordings only)
  LotOptions lot;
  std::string name;                            // in the file; empty: "lot of N units"
  LotMemberOptions members;
  std::filesystem::path out;                   // the lot file
  bool resume = false;

  // `--set`'s key=value pairs: lot.* keys into `lot` (LotOptions::table), every other into `structure`.
  // Error naming a bad lot.* key or value.
  void set(const OptionMap& options);
  std::string validate() const;
  // Of every input but out and resume, and of the contents of the files named: a resume with others is refused.
  std::string fingerprint() const;
};

struct LotLearnResult {
  LotModel lot;
  nlohmann::json file;      // what the lot file holds
  double mode_share = 0.0;  // of the standardised variance held by the modes
};

// Learns the lot and writes options.out (a gyrosid-prior/1 file with its population). Error naming the option
// or file for a bad request.
LotLearnResult run_lot_learn(const LotLearnOptions& options);

struct LotScreenOptions {
  std::string prior;                    // the lot file
  std::vector<std::string> recordings;  // each unit screened on its own
  ScreenOptions screen;
  std::filesystem::path out;            // directory
  bool resume = false;
  bool keep_in_family = true;           // false: the result keeps only the units out of family (each is in its screen.json),
                                        // so a lot of any size is screened in bounded memory
  std::string validate() const;
  std::string fingerprint() const;
};

struct ScreenedUnit {
  std::string recording;
  std::filesystem::path dir;  // where its screen.json is
  ScreenResult result;
  double white_dph_at_1hz = 0.0;
  nlohmann::json file;        // what its screen.json holds
};

struct LotScreenResult {
  std::vector<ScreenedUnit> units;  // in order; every unit, or, without keep_in_family, those out of family
  std::size_t screened = 0;
  int out_of_family = 0;
};

// Screens every recording against the lot; writes each unit's screen.json (report/lot_report.h) and, for
// several, screens.csv.
LotScreenResult run_lot_screen(const LotScreenOptions& options);

// `calibrate --prior lot.json`: the request becomes a unit of the lot's - the grey-box model of the lot's
// structure (model and options replaced), the maximum a posteriori under its population.
void take_lot_prior(CalibrationRequest& request, const LotModel& lot);

}  // namespace gyrosid
