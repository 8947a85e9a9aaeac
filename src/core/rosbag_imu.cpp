#include "core/rosbag_imu.h"

#include "core/error.h"

#ifdef GYROSID_HAVE_ROSBAG

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <cstring>
#include <exception>
#include <vector>

#include "core/format.h"

namespace gyrosid {

namespace {

// sensor_msgs/Imu as ROS 1 serializes it (little-endian, packed; its MD5 sum pins this layout):
//   std_msgs/Header header        uint32 seq, time stamp (uint32 sec, uint32 nsec), string frame_id (uint32 length, bytes)
//   geometry_msgs/Quaternion orientation, float64[9] orientation_covariance
//   geometry_msgs/Vector3 angular_velocity [rad/s], float64[9] angular_velocity_covariance
//   geometry_msgs/Vector3 linear_acceleration [m/s^2], float64[9] linear_acceleration_covariance
constexpr const char* kImuType = "sensor_msgs/Imu";
constexpr const char* kImuMd5 = "6a62c6daae103f4ff57a132d6f95cec2";

template <typename T>
T read(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

class RosbagImuReader : public ImuLogReader {
 public:
  RosbagImuReader(const std::string& path, const std::string& topic);
  bool next(ImuLogSample& s) override;
  std::string where(std::uint64_t message) const override { return str_cat(path_, ": message ", message, " on ", topic_); }
  std::uint64_t position() const override { return count_ ? bytes_ * read_ / count_ : 0; }

 private:
  void check_connections();
  void decode(ImuLogSample& s);
  std::string path_, topic_;
  rosbag::Bag bag_;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  std::uint64_t read_ = 0, count_ = 0, bytes_ = 0;
  std::vector<std::uint8_t> buffer_;
};

RosbagImuReader::RosbagImuReader(const std::string& path, const std::string& topic) : path_(path), topic_(topic) {
  try {
    bag_.open(path, rosbag::bagmode::Read);
    bytes_ = bag_.getSize();
    view_ = std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(topic));
    count_ = view_->size();
    check_connections();
    it_ = view_->begin();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, ": cannot read the bag: ", e.what());
  }
  info_.ticks_per_second = 1'000'000'000;
  info_.time_source = str_cat(topic, " header.stamp [ns]");
  info_.has_accel = true;
}

void RosbagImuReader::check_connections() {
  if (count_ == 0) {
    rosbag::View all(bag_);
    std::vector<std::string> topics;
    for (const auto* c : all.getConnections()) topics.push_back(str_cat(c->topic, " (", c->datatype, ")"));
    fail(path_, ": no messages on topic '", topic_, "'; the bag has ", topics.empty() ? "no topics" : join(topics));
  }
  for (const auto* c : view_->getConnections()) {
    if (c->datatype != kImuType || c->md5sum != kImuMd5) {
      fail(path_, ": topic '", topic_, "' carries ", c->datatype, " (md5 ", c->md5sum, "), not ", kImuType, " (md5 ", kImuMd5, ")");
    }
  }
}

void RosbagImuReader::decode(ImuLogSample& s) {
  const std::size_t n = buffer_.size();
  const std::uint8_t* p = buffer_.data();
  if (n < 16) fail(where(read_), ": ", n, " bytes are too few for a sensor_msgs/Imu");
  const std::uint64_t frame_id = read<std::uint32_t>(p + 12);
  const std::uint64_t at = 16 + frame_id;  // after the header
  if (n < at + 4 * 8 + 9 * 8 + 3 * 8 + 9 * 8 + 3 * 8 + 9 * 8) fail(where(read_), ": ", n, " bytes are too few for a sensor_msgs/Imu");
  s.stamp = static_cast<std::int64_t>(read<std::uint32_t>(p + 4)) * 1'000'000'000 + read<std::uint32_t>(p + 8);
  const std::uint8_t* w = p + at + 13 * 8;  // angular_velocity, after orientation and its covariance
  const std::uint8_t* a = w + 12 * 8;       // linear_acceleration, after angular_velocity and its covariance
  for (std::size_t k = 0; k < 3; ++k) {
    s.gyro_radps[k] = read<double>(w + 8 * k);
    s.accel_mps2[k] = read<double>(a + 8 * k);
  }
}

bool RosbagImuReader::next(ImuLogSample& s) {
  if (it_ == view_->end()) return false;
  ++read_;
  try {
    const rosbag::MessageInstance& m = *it_;
    buffer_.resize(m.size());
    ros::serialization::OStream out(buffer_.data(), static_cast<std::uint32_t>(buffer_.size()));
    m.write(out);
    ++it_;
  } catch (const std::exception& e) {
    fail(where(read_), ": cannot read the message: ", e.what());
  }
  decode(s);
  s.location = read_;
  return true;
}

}  // namespace

bool rosbag_available() { return true; }

std::unique_ptr<ImuLogReader> open_rosbag_imu(const std::string& path, const std::string& topic) {
  return std::make_unique<RosbagImuReader>(path, topic);
}

}  // namespace gyrosid

#else

namespace gyrosid {

bool rosbag_available() { return false; }

std::unique_ptr<ImuLogReader> open_rosbag_imu(const std::string& path, const std::string&) {
  fail(path, ": this gyrosid was built without ROS 1 bag support (install Debian's librosbag-storage-dev and rebuild)");
}

}  // namespace gyrosid

#endif
