// The grey-box model as dependency-free C99: polynomial and surface data, the scale-factor error and the
// steady-state compensation that inverts the forward model (GyroErrorModel::inverse) by safeguarded Newton.
#include <iomanip>

#include "model/greybox_model.h"
#include "model/spline_surface_c.h"

namespace gyrosid {
namespace {

void emit_polynomial_data(CExport& out, const std::string& name, const Polynomial& q) {
  out.array(name, q.coefficients.data(), q.coefficients.size());
  out.source << "static const double " << out.id(name) << "_ref = " << std::hexfloat << q.reference << std::defaultfloat << ";\n";
}

void emit_polynomial_function(CExport& out) {
  out.source << "\nstatic double " << out.id("poly") << "(const double* c, int n, double ref, double x, double* slope) {\n"
             << "  double v = 0.0, d = 0.0, u = x - ref;\n  int i;\n"
             << "  for (i = n - 1; i >= 0; --i) v = v * u + c[i];\n"
             << "  for (i = n - 1; i >= 1; --i) d = d * u + (double)i * c[i];\n"
             << "  if (slope) *slope = d;\n  return v;\n}\n";
}

// dSF(T, w) and its slope in w (GyroErrorModel::scale_factor_error).
void emit_scale_factor_error(CExport& out, const GyroErrorModel& e) {
  const std::string p = out.prefix;
  out.source << "\n/* Scale-factor error dSF(T, w) and its slope in w (GyroErrorModel::scale_factor_error). */\n"
             << "static double " << p << "_sf_error(double t, double w, double* slope) {\n"
             << "  double st, sw, value;\n"
             << "  value = " << p << "_poly(" << p << "_sf_t, " << e.scale_factor_temperature.coefficients.size() << ", " << p
             << "_sf_t_ref, t, &st) + " << p << "_poly(" << p << "_sf_w, " << e.scale_factor_rate.coefficients.size() << ", " << p
             << "_sf_w_ref, w, &sw);\n"
             << "  *slope = sw;\n";
  if (e.scale_factor_surface) out.source << "  { double ds; value += " << p << "_surface(t, w, &ds); *slope += ds; }\n";
  out.source << "  if (w > 0) value += 0.5 * " << e.scale_factor_asymmetry << ";\n"
             << "  if (w < 0) value -= 0.5 * " << e.scale_factor_asymmetry << ";\n"
             << "  return value;\n}\n";
}

// Solves w (1 + dSF(T, w)) + d = w_meas for w: bracketed Newton (GyroErrorModel::inverse).
void emit_predict(CExport& out, const GyroErrorModel& e, int accel_index) {
  const std::string p = out.prefix;
  out.source << "\n/* Steady-state compensation: solves w (1 + dSF(T, w)) + d = w_meas (GyroErrorModel::inverse). */\n"
             << "double " << p << "_predict(const double* x) {\n"
             << "  const double t = x[1];\n"
             << "  double d = " << e.bias_radps << " + " << p << "_poly(" << p << "_bias_t, " << e.bias_temperature_radps.coefficients.size()
             << ", " << p << "_bias_t_ref, t, 0);\n";
  if (accel_index >= 0) {
    out.source << "  d += " << e.g_sensitivity.x() << " * x[" << accel_index << "] + " << e.g_sensitivity.y() << " * x[" << accel_index + 1
               << "] + " << e.g_sensitivity.z() << " * x[" << accel_index + 2 << "];\n";
  }
  out.source << "  {\n    const double target = x[0] - d;\n"
             << "    double w = target, step = 1e-6 * (1.0 + fabs(target)), lo = w, hi = w, slope, f, next;\n    int iter;\n"
             << "#define PHI(W) ((W) * (1.0 + " << p << "_sf_error(t, (W), &slope)) - target)\n"
             << "    while (PHI(lo) > 0) lo -= (step *= 2.0);\n"
             << "    step = 1e-6 * (1.0 + fabs(target));\n"
             << "    while (PHI(hi) < 0) hi += (step *= 2.0);\n"
             << "    w = 0.5 * (lo + hi);\n"
             << "    for (iter = 0; iter < 200; ++iter) {\n"
             << "      const double sf = " << p << "_sf_error(t, w, &slope);\n"
             << "      f = w * (1.0 + sf) - target;\n"
             << "      slope = 1.0 + sf + w * slope;\n"
             << "      if (f == 0.0) break;\n"
             << "      if (f < 0) lo = w; else hi = w;\n"
             << "      next = slope > 0 ? w - f / slope : 0.5 * (lo + hi);\n"
             << "      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);\n"
             << "      if (fabs(next - w) <= 4e-16 * fmax(1.0, fabs(w)) || hi - lo <= 4e-16 * fmax(1.0, fabs(w))) { w = next; break; }\n"
             << "      w = next;\n    }\n#undef PHI\n"
             << "    return x[0] - w;\n  }\n}\n";
}

}  // namespace

void GreyboxModel::export_c_body(CExport& out) const {
  const GyroErrorModel& e = errors_;
  emit_polynomial_data(out, "bias_t", e.bias_temperature_radps);
  emit_polynomial_data(out, "sf_t", e.scale_factor_temperature);
  emit_polynomial_data(out, "sf_w", e.scale_factor_rate);
  if (e.scale_factor_surface) emit_spline_surface_data(out, "", *e.scale_factor_surface);
  out.source << std::hexfloat;
  emit_polynomial_function(out);
  if (e.scale_factor_surface) {
    emit_spline_surface_function(out, "", static_cast<int>(e.scale_factor_surface->x().size()),
                                 static_cast<int>(e.scale_factor_surface->y().size()));
  }
  emit_scale_factor_error(out, e);
  emit_predict(out, e, accel_index_);
  out.source << std::defaultfloat;
}

}  // namespace gyrosid
