// The sports shipped in rules/ that the tests of "every shipped sport" run: a new sport joins
// them here.
#pragma once

#include <array>

namespace quantum::test {

inline constexpr std::array kShippedSports = {"airhockey", "handball", "basketball", "keepaway", "practice", "soccer", "volleyball"};

}  // namespace quantum::test
