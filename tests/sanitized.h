// The size of a randomized or whole-scene test: its full count in the Release suite, a smaller one
// under AddressSanitizer + UndefinedBehaviorSanitizer, which run the same code paths about ten
// times slower. The sanitized suite looks for memory errors and undefined behaviour along every
// path, not for the rare case a thousandth trial finds: the Release suite runs every trial.
#pragma once

namespace lacet::test {

#ifdef LACET_SANITIZED
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

// `release` in the Release suite, `sanitized` under the sanitizers.
constexpr int sanitizedOr(int release, int sanitized) { return kSanitized ? sanitized : release; }

}  // namespace lacet::test
