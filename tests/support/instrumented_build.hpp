#pragma once
// Whether this test binary is built with AddressSanitizer (scripts/test --sanitize). An
// instrumented build runs Porter's code several times slower, so a test whose subject is a
// real-time rate (the simulated MID-360 sending 200,000 points/s through the driver) cannot
// hold it there; such a test skips under ASan and says why, its decoding and layout checks are
// covered by the unit tests that do run instrumented.

namespace porter::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kInstrumentedBuild = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kInstrumentedBuild = true;
#else
inline constexpr bool kInstrumentedBuild = false;
#endif
#else
inline constexpr bool kInstrumentedBuild = false;
#endif

}  // namespace porter::test
