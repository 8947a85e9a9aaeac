// The recording format, rule by rule (docs/recording_format.md).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <unistd.h>
#include <filesystem>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/recording.h"
#include "core/recording_reader.h"
#include "error_of.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;

std::string error_of(const std::string& text, const std::string& source = "rec.csv") {
  return testing_support::error_of([&] { parse_recording(text, source); });
}

// The example of docs/recording_format.md, verbatim.
const char* kSpecExample =
    "# format: gyrosid-recording/1\n"
    "# sensor: open-loop FOG, simulated\n"
    "# sample_rate_hz: 1\n"
    "t_s,ref_rate_dps,temp_c,gyro_dps,chamber_temp_c\n"
    "0,-100,-20.000,-99.9512,-20.000\n"
    "1,-99.5,-20.000,-99.4603,-19.917\n";

TEST(Recording, ReadsTheSpecExample) {
  const Recording r = parse_recording(kSpecExample, "example.csv");
  EXPECT_EQ(r.kind(), RecordingKind::single);
  ASSERT_EQ(r.rows(), 2u);
  EXPECT_EQ(r.column("gyro_dps")[0], -99.9512);
  EXPECT_EQ(r.column("chamber_temp_c")[1], -19.917);
  EXPECT_EQ(r.meta("sensor").value(), "open-loop FOG, simulated");
  EXPECT_EQ(r.meta("sample_rate_hz").value(), "1");
}

TEST(Recording, ColumnsByNameInAnyOrderWithAuxiliaryChannelsAndCrLf) {
  const Recording r = parse_recording(
      "# seed: 3\r\n# my_key: kept\r\n# a free comment line\r\n"
      "supply_v,gyro_dps,temp_c,t_s,ref_rate_dps\r\n"
      "5.01, 1.5e0 ,25,0x1p-1,1\r\n"
      "nan,2.5,25,1,2\r\n",
      "aux.csv");
  EXPECT_EQ(r.column("t_s")[0], 0.5);                  // hexadecimal float: strtod-readable
  EXPECT_EQ(r.column("gyro_dps")[0], 1.5);
  EXPECT_TRUE(std::isnan(r.column("supply_v")[1]));     // nan allowed in an optional column
  EXPECT_EQ(r.meta("my_key").value(), "kept");          // unknown metadata kept
  EXPECT_FALSE(r.meta("a").has_value());                 // a comment is not metadata
}

TEST(Recording, ErrorsNameFileLineAndColumn) {
  const std::string header = "t_s,ref_rate_dps,temp_c,gyro_dps\n";
  EXPECT_THAT(error_of(header + "0,1,25,1\n1,abc,25,1\n"), HasSubstr("rec.csv:3: column 'ref_rate_dps'"));
  EXPECT_THAT(error_of(header + "0,1,25,1\n1,1,25\n"), HasSubstr("rec.csv:3: row has 3 cells"));
  EXPECT_THAT(error_of(header + "0,1,25,1\n1,1,nan,1\n"), HasSubstr("rec.csv:3: column 'temp_c'"));
  EXPECT_THAT(error_of(header + "0,1,25,1\n0,1,25,1\n"), HasSubstr("rec.csv:3: column 't_s'"));
  EXPECT_THAT(error_of(header + "0,1,25,1\n2,1,25,1\n1,1,25,1\n"), HasSubstr("strictly increasing"));
  EXPECT_THAT(error_of("# x: 1\nt_s,ref_rate_dps,temp_c\n0,1,25\n"), HasSubstr("missing required column 'gyro_dps'"));
  EXPECT_THAT(error_of("# x: 1\nt_s,ref_rate_dps,temp_c\n0,1,25\n"), HasSubstr("rec.csv:2"));
  // The header's own line, also when comments or blank lines stand between it and the first row.
  EXPECT_THAT(error_of("t_s,ref_rate_dps,temp_c\n# note\n\n0,1,25\n"), HasSubstr("rec.csv:1: missing required column"));
  EXPECT_THAT(error_of("t_s,t_s,ref_rate_dps,temp_c,gyro_dps\n"), HasSubstr("appears twice"));
  EXPECT_THAT(error_of("# only: metadata\n"), HasSubstr("no header row"));
  EXPECT_THAT(error_of(header + "0,1,25,1.5.2\n"), HasSubstr("'1.5.2' is not a number"));
}

TEST(Recording, TriadColumnsAndPerAxisTemperatures) {
  const std::string header = "t_s,ref_rate_x_dps,ref_rate_y_dps,ref_rate_z_dps,gyro_x_dps,gyro_y_dps,gyro_z_dps";
  const Recording r = parse_recording(header + ",temp_x_c,temp_y_c,temp_z_c,position_id\n0,1,2,3,1,2,3,20,21,22,4\n", "t.csv");
  EXPECT_EQ(r.kind(), RecordingKind::triad);
  EXPECT_EQ(required_columns(RecordingKind::triad, r).back(), "temp_z_c");
  // The temperature is optional (a static noise log has no thermometer), but per-axis probes come in threes.
  const Recording no_temp = parse_recording(header + "\n0,1,2,3,1,2,3\n", "t.csv");
  EXPECT_FALSE(no_temp.has("temp_c"));
  EXPECT_EQ(required_columns(RecordingKind::triad, no_temp).size(), 7u);
  EXPECT_THAT(error_of(header + ",temp_x_c\n0,1,2,3,1,2,3,20\n"), HasSubstr("missing required column 'temp_y_c'"));
  EXPECT_THAT(error_of(header + ",temp_c,position_id\n0,1,2,3,1,2,3,20,1.5\n"), HasSubstr("not an integer"));
}

TEST(Recording, WriteThenReadIsBitExact) {
  Recording r("<memory>");
  r.set_meta("sensor", "test");
  r.set_meta("seed", "9");
  r.set_column("t_s", {0.0, 0.1, 0.2});
  r.set_column("ref_rate_dps", {1.0 / 3.0, -2.5e-300, 1e300});
  r.set_column("temp_c", {25, 25.000000000000004, -60});
  r.set_column("gyro_dps", {std::nextafter(1.0, 2.0), -0.0, 123456789.123456789});
  r.set_column("supply_v", {5.0, std::nan(""), 5.0});
  const Recording back = parse_recording(format_recording(r), "back.csv");
  ASSERT_EQ(back.names(), r.names());
  for (const auto& name : r.names()) {
    for (std::size_t i = 0; i < r.rows(); ++i) {
      const double a = r.column(name)[i], b = back.column(name)[i];
      if (std::isnan(a)) {
        EXPECT_TRUE(std::isnan(b));
      } else {
        EXPECT_EQ(a, b) << name << "[" << i << "]";
        EXPECT_EQ(std::signbit(a), std::signbit(b));
      }
    }
  }
  EXPECT_EQ(back.meta("format").value(), "gyrosid-recording/1");
  EXPECT_EQ(back.meta("seed").value(), "9");
}

TEST(Recording, UniformSamplingIsCheckedNotAssumed) {
  const Recording ok = parse_recording("t_s,ref_rate_dps,temp_c,gyro_dps\n0,0,0,0\n0.5,0,0,0\n1,0,0,0\n", "u.csv");
  EXPECT_DOUBLE_EQ(uniform_sample_interval(ok, "test"), 0.5);
  const Recording bad = parse_recording("t_s,ref_rate_dps,temp_c,gyro_dps\n0,0,0,0\n1,0,0,0\n3,0,0,0\n4,0,0,0\n", "n.csv");
  try {
    uniform_sample_interval(bad, "the Allan deviation");
    FAIL() << "non-uniform sampling accepted";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("n.csv:4"));
    EXPECT_THAT(e.what(), HasSubstr("the Allan deviation needs uniform sampling"));
  }
}

TEST(Recording, MedianSampleIntervalIgnoresGapsAndJitter) {
  // Steps 0.9, 1.1, 1.0, 60 (a gap), 1.0: sorted 0.9, 1.0, 1.0, 1.1, 60 -> median 1.0 whatever the order.
  EXPECT_DOUBLE_EQ(median_sample_interval(std::vector<double>{0.0, 0.9, 2.0, 3.0, 63.0, 64.0}), 1.0);
  // A 10 Hz recording with one dropped sample.
  EXPECT_NEAR(median_sample_interval(std::vector<double>{0.0, 0.1, 0.2, 0.4, 0.5}), 0.1, 1e-15);
  EXPECT_DOUBLE_EQ(median_sample_interval(std::vector<double>{5.0}), 1.0);  // no step: the documented 1 s
}

// A file on disk for the streaming reader; removed with the test.
class RecordingFile {
 public:
  explicit RecordingFile(const std::string& text, const std::string& name = "stream.csv")
      : path_(std::filesystem::temp_directory_path() / ("gyrosid_reader_" + std::to_string(::getpid()) + "_" + name)) {
    std::ofstream(path_, std::ios::binary) << text;
  }
  ~RecordingFile() { std::filesystem::remove(path_); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Every value, bit for bit (nan where nan), and the same names and metadata.
void expect_same(const Recording& a, const Recording& b) {
  ASSERT_EQ(a.names(), b.names());
  ASSERT_EQ(a.rows(), b.rows());
  EXPECT_EQ(a.metadata(), b.metadata());
  for (const auto& name : a.names()) {
    for (std::size_t i = 0; i < a.rows(); ++i) {
      const double x = a.column(name)[i], y = b.column(name)[i];
      if (std::isnan(x)) EXPECT_TRUE(std::isnan(y)) << name << "[" << i << "]";
      else EXPECT_EQ(std::bit_cast<std::uint64_t>(x), std::bit_cast<std::uint64_t>(y)) << name << "[" << i << "]";
    }
  }
}

TEST(RecordingReader, FileInTinyChunksReadsAsTheTextInMemory) {
  // Lines longer than the 64-byte buffer (it grows), CRLF, a byte-order mark, comments and blank lines inside the
  // data, the last line without its newline; and the fuzz seeds.
  std::string text = "\xEF\xBB\xBF# format: gyrosid-recording/1\r\n# sensor: a long sensor description that does not fit in one small chunk\r\n";
  text += "t_s,ref_rate_dps,temp_c,gyro_dps,supply_v\r\n";
  for (int i = 0; i < 300; ++i) {
    text += std::to_string(i) + ".25," + std::to_string(i % 7 - 3) + ".125,2" + std::to_string(i % 10) + ",1.0000000000000002e-3," +
            (i % 11 ? "5.01" : "nan") + "\r\n";
    if (i == 100) text += "# a comment between rows\r\n\r\n";
  }
  text += "300,0,25,1,5";
  RecordingFile file(text);
  RecordingReader reader(file.path(), 64);
  const Recording streamed = read_recording(reader);
  expect_same(streamed, parse_recording(text, file.path().string()));
  ASSERT_EQ(streamed.rows(), 301u);
  // Lines: header on 3, rows on 4... until the comment and the blank line after row 100 (line 104).
  EXPECT_EQ(streamed.row_location(0), file.path().string() + ":4");
  EXPECT_EQ(streamed.row_location(100), file.path().string() + ":104");
  EXPECT_EQ(streamed.row_location(101), file.path().string() + ":107");
  EXPECT_EQ(streamed.row_location(300), file.path().string() + ":306");
  EXPECT_EQ(count_recording_rows(file.path()), 301u);
  for (const char* seed : {"crlf_channels.csv", "format_example.csv", "triad.csv"}) {
    std::ifstream in(std::string(GYROSID_SOURCE_DIR) + "/tests/fuzz/seeds/recording/" + seed, std::ios::binary);
    const std::string seed_text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    RecordingFile seed_file(seed_text, seed);
    RecordingReader seed_reader(seed_file.path(), 16);
    expect_same(read_recording(seed_reader), parse_recording(seed_text, seed_file.path().string()));
  }
}

TEST(RecordingReader, NumbersAsStrtodReadsThem) {
  // std::from_chars takes the common forms; a leading '+', hexadecimal and out-of-range values fall back to
  // strtod in the C locale (inf for an overflow, the subnormal for a tiny value) - the format's definition.
  const Recording r = parse_recording(
      "t_s,ref_rate_dps,gyro_dps,supply_v\n"
      "+1,0x1.8p1,1e-310,1e400\n"
      "2,-0.1,.5,-1e-400\n"
      "3,1.,5e+0,INF\n",
      "n.csv");
  EXPECT_EQ(r.column("t_s")[0], 1.0);
  EXPECT_EQ(r.column("ref_rate_dps")[0], 3.0);
  EXPECT_EQ(r.column("gyro_dps")[0], std::strtod("1e-310", nullptr));
  EXPECT_EQ(r.column("supply_v")[0], HUGE_VAL);
  EXPECT_EQ(r.column("ref_rate_dps")[1], std::strtod("-0.1", nullptr));
  EXPECT_EQ(r.column("gyro_dps")[1], 0.5);
  EXPECT_EQ(r.column("supply_v")[1], 0.0);
  EXPECT_TRUE(std::signbit(r.column("supply_v")[1]));
  EXPECT_EQ(r.column("ref_rate_dps")[2], 1.0);
  EXPECT_EQ(r.column("supply_v")[2], HUGE_VAL);
  // inf is a number, but not a finite one: refused in a required column like nan.
  EXPECT_THAT(error_of("t_s,ref_rate_dps,gyro_dps\n0,1,1e400\n"), HasSubstr("rec.csv:2: column 'gyro_dps': 'inf' in a required column"));
  EXPECT_THAT(error_of("t_s,ref_rate_dps,gyro_dps\n0,1,0x\n"), HasSubstr("cell '0x' is not a number"));
}

TEST(RecordingReader, KeepsOnlyTheColumnsAskedForAndChecksTheRest) {
  const std::string text = "t_s,ref_rate_dps,temp_c,gyro_dps,supply_v\n0,1,25,1,5\n1,1,25,1,5\n";
  RecordingFile file(text);
  const Recording two = read_recording(file.path(), {"t_s", "gyro_dps", "not_there"});
  EXPECT_EQ(two.names(), (std::vector<std::string>{"t_s", "gyro_dps"}));
  EXPECT_EQ(two.rows(), 2u);
  // A column not kept is still read: a bad cell there is the same error.
  RecordingFile bad("t_s,ref_rate_dps,temp_c,gyro_dps,supply_v\n0,1,25,1,5\n1,1,25,1,five\n", "bad.csv");
  EXPECT_THAT(testing_support::error_of([&] { read_recording(bad.path(), {"t_s", "gyro_dps"}); }),
              HasSubstr("bad.csv:3: column 'supply_v': cell 'five' is not a number"));
}

TEST(RecordingReader, TemperatureIsOptionalButCheckedWhereRecorded) {
  const Recording r = parse_recording("t_s,ref_rate_dps,gyro_dps\n0,0,0.1\n0.01,0,-0.2\n", "static.csv");
  EXPECT_EQ(r.kind(), RecordingKind::single);
  EXPECT_FALSE(r.has("temp_c"));
  EXPECT_EQ(required_columns(RecordingKind::single, r), (std::vector<std::string>{"t_s", "ref_rate_dps", "gyro_dps"}));
  EXPECT_THAT(testing_support::error_of([&] { require_column(r, "temp_c", "the model takes the temperature as an input"); }),
              HasSubstr("static.csv: no column 'temp_c': the model takes the temperature as an input"));
  // Recorded, the temperature is held to the required columns' rules.
  EXPECT_THAT(error_of("t_s,ref_rate_dps,temp_c,gyro_dps\n0,1,nan,1\n"), HasSubstr("rec.csv:2: column 'temp_c'"));
}

TEST(AtomicFile, FailedWriteLeavesNothingBehind) {
  const auto dir = std::filesystem::temp_directory_path() / "gyrosid_atomic_test";
  std::filesystem::remove_all(dir);
  const auto target = dir / "sub" / "result.csv";
  EXPECT_THROW(write_file_atomic(target, [](std::ostream& out) {
                 out << "half";
                 throw Error("writer failed");
               }),
               Error);
  EXPECT_FALSE(std::filesystem::exists(target));
  EXPECT_TRUE(std::filesystem::is_empty(dir / "sub"));  // no temporary left either
  write_file_atomic(target, "complete\n");
  std::ifstream in(target);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "complete");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrosid
