#include "model/spline_surface_c.h"

#include <vector>

namespace gyrosid {

void emit_spline_surface_data(CExport& out, const std::string& stem, const SplineSurface& s) {
  const auto nx = static_cast<Eigen::Index>(s.x().size()), ny = static_cast<Eigen::Index>(s.y().size());
  out.array(stem + "sx", s.x().data(), s.x().size());
  out.array(stem + "sy", s.y().data(), s.y().size());
  auto grid = [&](const std::string& name, const Eigen::MatrixXd& m) {
    std::vector<double> v;  // row-major: [i * ny + j]
    for (Eigen::Index i = 0; i < nx; ++i)
      for (Eigen::Index j = 0; j < ny; ++j) v.push_back(m(i, j));
    out.array(stem + name, v.data(), v.size());
  };
  grid("sf", s.values());
  grid("sfx", s.d_dx());
  grid("sfy", s.d_dy());
  grid("sfxy", s.d2_dxdy());
}

void emit_spline_surface_function(CExport& out, const std::string& stem, int nx, int ny) {
  const std::string p = out.id(stem);  // "<prefix>_<stem>", the arrays' common stem
  const std::string sx = p + "sx", sy = p + "sy";
  out.source << "\nstatic int " << p << "locate(const double* k, int n, double v) {\n"
             << "  int i = 0;\n  while (i < n - 2 && v >= k[i + 1]) ++i;\n  return i;\n}\n"
             << "\n/* Bicubic Hermite patch of the spline surface; held at the edge outside the grid. */\n"
             << "static double " << p << "surface(double x, double y, double* d_dy) {\n"
             << "  const int xo = x < " << sx << "[0] || x > " << sx << "[" << nx - 1 << "];\n"
             << "  const int yo = y < " << sy << "[0] || y > " << sy << "[" << ny - 1 << "];\n"
             << "  int i, j, a, b;\n  double hx, hy, u, v, bu[4], bv[4], dv[4], val = 0.0, dy = 0.0;\n"
             << "  if (x < " << sx << "[0]) x = " << sx << "[0];\n"
             << "  if (x > " << sx << "[" << nx - 1 << "]) x = " << sx << "[" << nx - 1 << "];\n"
             << "  if (y < " << sy << "[0]) y = " << sy << "[0];\n"
             << "  if (y > " << sy << "[" << ny - 1 << "]) y = " << sy << "[" << ny - 1 << "];\n"
             << "  i = " << p << "locate(" << sx << ", " << nx << ", x);\n"
             << "  j = " << p << "locate(" << sy << ", " << ny << ", y);\n"
             << "  hx = " << sx << "[i + 1] - " << sx << "[i];\n  hy = " << sy << "[j + 1] - " << sy << "[j];\n"
             << "  u = (x - " << sx << "[i]) / hx;\n  v = (y - " << sy << "[j]) / hy;\n"
             << "  { const double u2 = u * u, u3 = u2 * u, v2 = v * v, v3 = v2 * v;\n"
             << "    bu[0] = 2 * u3 - 3 * u2 + 1; bu[1] = -2 * u3 + 3 * u2; bu[2] = u3 - 2 * u2 + u; bu[3] = u3 - u2;\n"
             << "    bv[0] = 2 * v3 - 3 * v2 + 1; bv[1] = -2 * v3 + 3 * v2; bv[2] = v3 - 2 * v2 + v; bv[3] = v3 - v2;\n"
             << "    dv[0] = 6 * v2 - 6 * v; dv[1] = -6 * v2 + 6 * v; dv[2] = 3 * v2 - 4 * v + 1; dv[3] = 3 * v2 - 2 * v; }\n"
             << "  for (a = 0; a < 4; ++a) {\n    for (b = 0; b < 4; ++b) {\n"
             << "      const int ii = i + (a & 1), jj = j + (b & 1), at = ii * " << ny << " + jj;\n"
             << "      const double sx = a >= 2 ? hx : 1.0, sy = b >= 2 ? hy : 1.0;\n"
             << "      double c;\n"
             << "      if (a < 2 && b < 2) c = " << p << "sf[at];\n"
             << "      else if (a >= 2 && b < 2) c = sx * " << p << "sfx[at];\n"
             << "      else if (a < 2) c = sy * " << p << "sfy[at];\n"
             << "      else c = sx * sy * " << p << "sfxy[at];\n"
             << "      val += bu[a] * bv[b] * c;\n"
             << "      dy += bu[a] * dv[b] * c / hy;\n    }\n  }\n"
             << "  (void)xo;\n  *d_dy = yo ? 0.0 : dy;\n  return val;\n}\n";
}

}  // namespace gyrosid
