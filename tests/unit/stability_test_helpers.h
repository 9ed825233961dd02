// What the stability tests share (stability_test.cpp, stability_inputs_test.cpp): the non-finite
// floats they feed in.
#pragma once

#include <limits>

namespace puff::test {

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
inline constexpr float kInf = std::numeric_limits<float>::infinity();

}  // namespace puff::test
