#pragma once
// Whether this test binary runs under AddressSanitizer (the build-asan stage of .ci/run). The
// sanitizer stage is there to catch memory and undefined-behaviour errors in the project's code:
// a test that repeats the same code path over many real scenes, or times PCL's own matchers, runs
// one representative case there and every case in the release stage (docs/testing.md).

namespace radar_ndt {
namespace test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitizedBuild = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif
#else
inline constexpr bool kSanitizedBuild = false;
#endif

}  // namespace test
}  // namespace radar_ndt
