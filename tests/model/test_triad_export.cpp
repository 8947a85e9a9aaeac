// Triad model exports: the C99 compensation compiled and compared with the library's, and the Kalibr
// factorisation (I + M) = M_k C_gyro_i with M_k lower triangular and C_gyro_i a rotation.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/units.h"
#include "model/triad_export.h"
#include "model_samples.h"

namespace gyrosid {
namespace {

namespace fs = std::filesystem;

using testing_support::sample_triad;

TEST(TriadExport, KalibrFactorsAreLowerTriangularTimesARotation) {
  const TriadModel m = sample_triad();
  const KalibrImu k = kalibr_intrinsics(m);
  EXPECT_LT((k.m * k.c_gyro_i - (Eigen::Matrix3d::Identity() + m.misalignment)).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(k.m(0, 1), 0.0);
  EXPECT_EQ(k.m(0, 2), 0.0);
  EXPECT_EQ(k.m(1, 2), 0.0);
  for (int i = 0; i < 3; ++i) EXPECT_GT(k.m(i, i), 0.0);
  EXPECT_LT((k.c_gyro_i * k.c_gyro_i.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_NEAR(k.c_gyro_i.determinant(), 1.0, 1e-15);
  EXPECT_LT((k.a * k.c_gyro_i - *m.g_sensitivity).cwiseAbs().maxCoeff(), 1e-20);
  const std::string yaml = kalibr_imu_yaml(m, {{1e-4, 2e-4, 1.5e-4}, 100.0, "/imu0", "m.json"});
  EXPECT_NE(yaml.find("model: scale-misalignment"), std::string::npos);
  EXPECT_NE(yaml.find("gyroscope_noise_density: 0.0002"), std::string::npos);
  EXPECT_NE(yaml.find("[rad/s/sqrt(Hz)]"), std::string::npos);
}

TEST(TriadExport, CompiledCCompensationEqualsTheLibrarys) {
  const TriadModel m = sample_triad();
  const fs::path dir = fs::temp_directory_path() / "gyrosid_triad_export_c";
  fs::remove_all(dir);
  fs::create_directories(dir);
  export_triad_c(m, dir, "imu");
  std::ofstream driver(dir / "main.c");
  driver << "#include <stdio.h>\n#include \"imu.h\"\nint main(void) {\n  double g[3], t[3], f[3], w[3];\n"
         << "  while (scanf(\"%lf %lf %lf %lf %lf %lf %lf %lf %lf\", &g[0], &g[1], &g[2], &t[0], &t[1], &t[2], &f[0], &f[1], &f[2]) == 9) {\n"
         << "    imu_compensate(g, t, f, w);\n    printf(\"%.17g %.17g %.17g\\n\", w[0], w[1], w[2]);\n  }\n  return 0;\n}\n";
  driver.close();
  const std::string exe = (dir / "imu").string();
  const std::string compile = "cc -std=c99 -pedantic -Wall -Werror -O2 -o " + exe + " " + (dir / "imu.c").string() + " " + (dir / "main.c").string() + " -lm 2>&1";
  ASSERT_EQ(std::system(compile.c_str()), 0) << compile;
  TriadData d;
  const int n = 40;
  d.gyro.resize(n, 3);
  d.temp_c.resize(n, 3);
  d.accel.resize(n, 3);
  std::ofstream in(dir / "in.txt");
  in.precision(17);
  for (int k = 0; k < n; ++k) {
    d.t_s.push_back(k);
    d.gyro.row(k) << std::sin(0.3 * k), 0.7 * std::cos(0.2 * k), -1.5 + 0.07 * k;
    d.temp_c.row(k) << -30.0 + 2 * k, 25.0, 70.0 - k;
    d.accel.row(k) << 0.1 * k, -9.8, 1.0;
    for (int a = 0; a < 3; ++a) in << d.gyro(k, a) << " ";
    for (int a = 0; a < 3; ++a) in << d.temp_c(k, a) << " ";
    for (int a = 0; a < 3; ++a) in << d.accel(k, a) << " ";
    in << "\n";
  }
  in.close();
  const Eigen::MatrixX3d expected = m.compensate(d);
  FILE* pipe = popen((exe + " < " + (dir / "in.txt").string()).c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  for (int k = 0; k < n; ++k) {
    for (int a = 0; a < 3; ++a) {
      double w = 0;
      ASSERT_EQ(std::fscanf(pipe, "%lf", &w), 1);
      EXPECT_NEAR(w, expected(k, a), 1e-14 * std::max(1.0, std::abs(expected(k, a)))) << k << " " << a;
    }
  }
  pclose(pipe);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace gyrosid
