#pragma once
// Numeric constants every layer shares (one definition: solver files that
// each defined their own could not be compiled together).
#include <numbers>

namespace gistream {

inline constexpr float kPi = std::numbers::pi_v<float>;

}  // namespace gistream
