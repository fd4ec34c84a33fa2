#pragma once
// For fuzz targets that decode lcm types: lcm-gen's decoders resize every counted array to the
// count read from the buffer before checking that the buffer holds that many elements, so a
// corrupt count asks for up to 16 GiB. Outside sanitizer builds (the bounded random-input test),
// operator new refuses blocks above 1 MiB (more than any message these targets decode) with std::bad_alloc, which the decode wrapper treats
// as a message that does not decode (as porter::LcmBus does), keeping each run fast. Under ASan
// (scripts/fuzz) the override is left out and libFuzzer's own -malloc_limit_mb reports them.
// Include from exactly one source of a fuzz binary.

#include <cstddef>
#include <cstdlib>
#include <new>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PORTER_FUZZ_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define PORTER_FUZZ_ASAN 1
#endif

#ifndef PORTER_FUZZ_ASAN
void* operator new(std::size_t size) {
  if (size > (std::size_t{1} << 20)) throw std::bad_alloc();
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#endif
