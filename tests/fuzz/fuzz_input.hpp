// Turning a fuzzer's byte string into structured input, and the check macro
// every fuzz target uses.
//
// FuzzInput hands out bytes, integers and doubles from the front of the
// buffer and zeros once it runs dry, so every byte string is a valid input
// and a mutation of one byte changes one value. Doubles come in three
// flavours chosen by a selector byte, so the fuzzer reaches all of them
// without having to guess bit patterns: raw IEEE bits (NaN, infinities,
// subnormals, 1e300 all reachable), a small integer grid (duplicates,
// collinear and coplanar sets, exact touching), and a table of extremes.
//
// HEDRA_FUZZ_CHECK prints the failed condition and the byte count, then
// aborts: that is how libFuzzer (and the standalone driver) learn of a
// finding. It is for the fuzz targets only; the libraries never abort.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#define HEDRA_FUZZ_CHECK(condition, ...)                                                          \
  do {                                                                                            \
    if (!(condition)) {                                                                           \
      std::fprintf(stderr, "fuzz check failed at %s:%d: %s\n  ", __FILE__, __LINE__, #condition); \
      std::fprintf(stderr, __VA_ARGS__);                                                          \
      std::fprintf(stderr, "\n");                                                                 \
      std::abort();                                                                               \
    }                                                                                             \
  } while (0)

namespace hedra::fuzz {

class FuzzInput {
 public:
  FuzzInput(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  std::size_t remaining() const { return size_ - offset_; }

  std::uint8_t byte() { return offset_ < size_ ? data_[offset_++] : 0; }

  // A value in [0, bound) (bound > 0).
  unsigned below(unsigned bound) {
    unsigned v = byte();
    if (bound > 256) v = (v << 8) | byte();
    return v % bound;
  }

  double raw_double() {
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i) bits = (bits << 8) | byte();
    double d;
    std::memcpy(&d, &bits, sizeof d);
    return d;
  }

  // One of the three flavours described above.
  double any_double() {
    static const double extremes[] = {0.0,
                                      -0.0,
                                      1.0,
                                      -1.0,
                                      0.5,
                                      1e-300,
                                      -1e-300,
                                      1e300,
                                      -1e300,
                                      std::numeric_limits<double>::denorm_min(),
                                      std::numeric_limits<double>::min(),
                                      std::numeric_limits<double>::max(),
                                      std::numeric_limits<double>::lowest(),
                                      std::numeric_limits<double>::epsilon(),
                                      1.0 + std::numeric_limits<double>::epsilon(),
                                      1e6,
                                      1e6 + 1e-6,
                                      1e-9,
                                      std::numeric_limits<double>::infinity(),
                                      -std::numeric_limits<double>::infinity(),
                                      std::numeric_limits<double>::quiet_NaN()};
    const std::uint8_t selector = byte();
    switch (selector % 4) {
      case 0:
        return raw_double();
      case 1:
      case 2:
        return static_cast<double>(static_cast<int>(byte()) - 128) / 16.0;  // grid of step 1/16
      default:
        return extremes[byte() % (sizeof extremes / sizeof extremes[0])];
    }
  }

  // A double that is finite and within [-limit, limit]: mostly the grid,
  // sometimes raw bits folded into range.
  double finite_double(double limit) {
    double d = any_double();
    if (!std::isfinite(d)) d = 0.0;
    if (std::fabs(d) > limit) d = std::fmod(d, limit);
    return d;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

}  // namespace hedra::fuzz
