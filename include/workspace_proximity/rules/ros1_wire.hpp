#pragma once
/// A bounds-checked reader of the ROS 1 wire format, ROS-free: little-endian numbers, strings
/// and variable arrays behind a uint32 length, fixed arrays inline, time and duration as two
/// 32-bit integers. Every read checks the bytes left; the first failure sticks (later reads
/// return zeros and move nothing), so a decoder reads a whole message and asks once.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

#include <Eigen/Core>

#include "workspace_proximity/rules/stamp.hpp"

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "ros1_wire.hpp reads little-endian bytes by copying them: a big-endian host needs swaps"
#endif

namespace workspace_proximity {

/// Why a read failed.
enum class WireError : std::uint8_t {
  kNone,
  kTruncated,  ///< a fixed-size read ran past the buffer's end
  kBadLength,  ///< a length prefix asks for more bytes than are left
};

/// Reads values in order from one serialized message. Holds views, copies nothing.
class WireReader {
 public:
  WireReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool ok() const { return error_ == WireError::kNone; }
  WireError error() const { return error_; }
  /// Bytes read so far (where a failure happened, when one did).
  std::size_t offset() const { return offset_; }
  std::size_t remaining() const { return size_ - offset_; }
  /// What the failure was, as text (an empty string while ok()).
  const char* errorText() const {
    switch (error_) {
      case WireError::kNone: return "";
      case WireError::kTruncated: return "the message ends inside a field";
      case WireError::kBadLength: return "a length prefix is larger than the bytes left";
    }
    return "unknown wire error";
  }

  std::uint8_t u8() { return scalar<std::uint8_t>(); }
  bool boolean() { return u8() != 0; }
  std::uint32_t u32() { return scalar<std::uint32_t>(); }
  std::int32_t i32() { return scalar<std::int32_t>(); }
  std::uint64_t u64() { return scalar<std::uint64_t>(); }
  std::int64_t i64() { return scalar<std::int64_t>(); }
  float f32() { return scalar<float>(); }
  double f64() { return scalar<double>(); }

  /// A ROS time (uint32 seconds, uint32 nanoseconds) as nanoseconds.
  Stamp time() {
    const std::uint32_t sec = u32();
    const std::uint32_t nsec = u32();
    return static_cast<Stamp>(sec) * 1000000000 + nsec;
  }
  /// A ROS duration (int32 seconds, int32 nanoseconds) as nanoseconds.
  Stamp duration() {
    const std::int32_t sec = i32();
    const std::int32_t nsec = i32();
    return static_cast<Stamp>(sec) * 1000000000 + nsec;
  }

  /// A string: a view into the buffer (valid while the buffer is).
  std::string_view string() {
    const std::uint32_t n = u32();
    if (!ok()) return {};
    if (n > remaining()) {
      fail(WireError::kBadLength);
      return {};
    }
    std::string_view s(reinterpret_cast<const char*>(data_ + offset_), n);
    offset_ += n;
    return s;
  }

  /// A variable array's length, refused (kBadLength) when `count * min_element_bytes` exceeds
  /// the bytes left: no element of any ROS type is smaller than its fixed part, so a larger
  /// count cannot be honest and is never used to size anything.
  std::uint32_t arrayLength(std::size_t min_element_bytes) {
    const std::uint32_t n = u32();
    if (!ok()) return 0;
    if (min_element_bytes > 0 && n > remaining() / min_element_bytes) {
      fail(WireError::kBadLength);
      return 0;
    }
    return n;
  }

  /// Skips `n` bytes (fixed-size fields nobody reads).
  void skip(std::size_t n) {
    if (!ok()) return;
    if (n > remaining()) {
      fail(WireError::kTruncated);
      return;
    }
    offset_ += n;
  }
  /// Skips a variable array of fixed-size elements.
  void skipArray(std::size_t element_bytes) {
    const std::uint32_t n = arrayLength(element_bytes);
    skip(static_cast<std::size_t>(n) * element_bytes);
  }
  /// Skips a string[].
  void skipStringArray() {
    const std::uint32_t n = arrayLength(4);
    for (std::uint32_t i = 0; i < n && ok(); ++i) string();
  }

  /// Reads `n` doubles into `out` (a fixed float64[n] array).
  void f64s(double* out, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) out[i] = f64();
  }
  /// geometry_msgs/Point or Vector3: three float64.
  Eigen::Vector3d vector3() {
    const double x = f64();
    const double y = f64();
    const double z = f64();
    return Eigen::Vector3d(x, y, z);
  }
  /// geometry_msgs/Quaternion as x, y, z, w.
  Eigen::Vector4d quaternion() {
    const double x = f64();
    const double y = f64();
    const double z = f64();
    const double w = f64();
    return Eigen::Vector4d(x, y, z, w);
  }

  void fail(WireError e) {
    if (error_ == WireError::kNone) error_ = e;
  }

 private:
  template <typename T>
  T scalar() {
    if (!ok()) return T();
    if (sizeof(T) > remaining()) {
      fail(WireError::kTruncated);
      return T();
    }
    T v;
    std::memcpy(&v, data_ + offset_, sizeof(T));
    offset_ += sizeof(T);
    return v;
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
  WireError error_ = WireError::kNone;
};

/// Fixed wire sizes of the standard types (bytes), for arrayLength's lower bounds.
namespace wire_size {
constexpr std::size_t kPoint = 24;                      ///< geometry_msgs/Point, Vector3
constexpr std::size_t kPose = 56;                       ///< geometry_msgs/Pose
constexpr std::size_t kPoseWithCovariance = 56 + 288;   ///< pose + float64[36]
constexpr std::size_t kTwist = 48;                      ///< geometry_msgs/Twist, Accel
constexpr std::size_t kTwistWithCovariance = 48 + 288;  ///< twist + float64[36]
constexpr std::size_t kHeaderMin = 16;                  ///< seq, stamp, empty frame_id
}  // namespace wire_size

}  // namespace workspace_proximity
