#include "pipeline/triad_job.h"

#include "report/triad_json.h"

namespace gyrosid {

TriadCalibration calibrate_triad(const Recording& recording, const OptionMap& options) {
  TriadCalibration c;
  c.options.table().apply(options);
  c.fit = fit_triad(make_triad_data(recording), c.options, recording.meta("reference").value_or(""));
  c.file = triad_fit_json(c.fit, {{"recording", recording.source()}, {"samples", recording.rows()}, {"options", options}});
  return c;
}

}  // namespace gyrosid
