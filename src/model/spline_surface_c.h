// A bicubic spline surface (sensor/spline_surface.h) as dependency-free C99, for the models' exports: its
// grid and Hermite corner data as arrays, and
//
//   static double <prefix>_<stem>surface(double x, double y, double* d_dy);
//
// evaluating the patch (value, and its slope in y), held at the edge outside the grid as the C++ clamp
// policy does.
#pragma once

#include <string>

#include "model/calibration_model.h"
#include "sensor/spline_surface.h"

namespace gyrosid {

// The arrays <stem>sx, <stem>sy, <stem>sf, <stem>sfx, <stem>sfy, <stem>sfxy (row-major [i * ny + j]).
void emit_spline_surface_data(CExport& out, const std::string& stem, const SplineSurface& surface);
// The functions <stem>locate and <stem>surface reading those arrays.
void emit_spline_surface_function(CExport& out, const std::string& stem, int nx, int ny);

}  // namespace gyrosid
