// An adaptive calibration session (gyrosid session; issue 32 item 2): a pilot, an update of the prior over
// sensors by what the unit recorded, and a redesign of the remaining time for the updated prior, repeated at
// stated checkpoints, then the final calibration on everything recorded.
//
//   segment 1   the design for the prior (sensor/sensor_prior.h) with the pilot's budget
//   update      every member's likelihood of everything recorded so far (design/sensor_posterior.h): the
//               tempered posterior; an interim calibration on the recording so far (with
//               session.measured_white_noise, the white noise the recording shows replaces every member's first)
//   segment k   the design for the posterior that continues the recorded segments from where the chamber is:
//               judged on recorded + new, the information the final calibration will have (design_problem.h)
//   final       the calibration on all segments, one recording
//
// With a true sensor (`truth`, simulation) each segment is the truth simulated on the whole programme so far and
// cut at the segment's start - the same seed gives the same earlier samples, so the segments join into the
// recording of one uninterrupted run; the session sees only those recordings. Without one it stops after
// designing a segment and waits for the lab's recording (<out>/segment_k/recording.csv, times from the
// segment's start); run again with resume to go on. Every file is written atomically and the session's
// state is its directory: a killed session resumed with the same inputs ends with the same bytes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solvers/common/options.h"

namespace gyrosid {

struct SessionOptions {
  std::string prior;                  // gyrosid-prior/1, or a sensor config (a prior of one sensor)
  std::string truth;                  // a sensor config to simulate (empty: the lab records each segment)
  std::filesystem::path out;
  double budget_min = 60.0;
  double pilot_min = 15.0;
  std::vector<double> updates_at_min; // further updates, minutes from the start (after the pilot, before the end)
  std::string model = "auto";         // the designs' model family (design/regressor.h), or auto: design_model (pipeline/design_job.h)
  std::string calibration;            // calibration config of the interim and final fits (empty: the design's)
  std::string envelope = "short,medium,long";
  std::string equipment = "builtin:equipment/thesis_lab.yaml";
  OptionMap settings;                 // design settings and nlopt options (gyrosid design --set)
  double min_effective_members = 2.0; // the posterior's tempering floor (design/sensor_posterior.h)
  double drop_share = 1e-3;           // members below this posterior share are left out of a redesign
  bool measured_white_noise = false;  // after each segment the recording's white noise replaces the members'
                                      // (measured worse on the five test sensors: experiments/adaptive_session)
  std::uint64_t seed = 1;             // the designs' and the truth's
  bool resume = false;
  std::function<void(const std::string&)> on_step;  // "segment 2/2: designing 45 min for 3 members"

  void bind(OptionTable& table);  // keys session.min_effective_members, session.drop_share, session.measured_white_noise
  // `--set`'s key=value pairs: the session.* keys into this struct (bind), every other into settings. Error
  // naming a bad session.* key or value.
  void set(const OptionMap& options);
  std::string validate() const;
  // Of every input but out and resume, and of the contents of the files named: a resume with others is refused.
  std::string fingerprint() const;
  std::vector<double> boundaries_min() const;  // each segment's end, minutes from the start
};

struct SessionResult {
  int segments_done = 0, segments = 0;
  std::optional<std::filesystem::path> waiting_for;  // the recording the lab must provide next
  std::filesystem::path model;                       // the final model (empty while waiting)
  nlohmann::json session;                            // what session.json holds
};

// Runs (or resumes) the session; writes under options.out (session.json, report.md, segment_k/..., and at
// the end recording.csv and model.json). Error naming the option or file for a bad request.
SessionResult run_session(const SessionOptions& options);

}  // namespace gyrosid
