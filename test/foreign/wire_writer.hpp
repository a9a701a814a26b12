#pragma once
/// Test-only writer of the ROS 1 wire format (little-endian; strings and variable arrays behind
/// a uint32 length), written from the format's description, not from the reader, so that a
/// decoder test compares against values put in by hand.

#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string_view>
#include <vector>

namespace wp_test {

struct WireWriter {
  std::vector<std::uint8_t> bytes;

  template <typename T>
  void raw(T v) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    bytes.insert(bytes.end(), b, b + sizeof(T));
  }
  void u8(std::uint8_t v) { raw(v); }
  void u32(std::uint32_t v) { raw(v); }
  void i32(std::int32_t v) { raw(v); }
  void u64(std::uint64_t v) { raw(v); }
  void i64(std::int64_t v) { raw(v); }
  void f32(float v) { raw(v); }
  void f64(double v) { raw(v); }
  void str(std::string_view s) {
    u32(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  void header(std::uint32_t seq, std::uint32_t sec, std::uint32_t nsec, std::string_view frame) {
    u32(seq);
    u32(sec);
    u32(nsec);
    str(frame);
  }
  void vec3(double x, double y, double z) {
    f64(x);
    f64(y);
    f64(z);
  }
  void quat(double x, double y, double z, double w) {
    vec3(x, y, z);
    f64(w);
  }
  void f64s(std::initializer_list<double> values) {
    for (double v : values) f64(v);
  }
  void f64s(const double* values, int n) {
    for (int i = 0; i < n; ++i) f64(values[i]);
  }
};

}  // namespace wp_test
