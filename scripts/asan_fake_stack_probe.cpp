// Issue 14: are AddressSanitizer's fake stack frames (detect_stack_use_after_return=1) aligned enough
// for the 64-byte AVX-512 stores GCC emits into over-aligned locals with -march=native?
//   g++ -O2 -march=native -fsanitize=address scripts/asan_fake_stack_probe.cpp -o /tmp/probe
//   ASAN_OPTIONS=detect_stack_use_after_return=1 /tmp/probe
// Prints each local's address modulo 64 (0 = aligned) and ends "ok"; a misaligned frame would SEGV on
// the aligned store (docs/validation.md §8).
#include <immintrin.h>

#include <cstdint>
#include <cstdio>

// A frame of ~6 KB, ASan's fake-stack size class 7, like run_fe_test's (0x1880 bytes).
__attribute__((noinline)) double large_frame(int n) {
  alignas(64) double a[8];
  volatile char pad[6000];
  pad[n % 6000] = 1;
#ifdef __AVX512F__
  _mm512_store_pd(a, _mm512_set1_pd(n));
#else
  for (double& x : a) x = n;
#endif
  std::printf("large frame: local %% 64 = %lu\n", static_cast<unsigned long>(reinterpret_cast<std::uintptr_t>(a) % 64));
  return a[3] + pad[0];
}

__attribute__((noinline)) double small_frame(int n) {
  alignas(64) double a[8];
#ifdef __AVX512F__
  _mm512_store_pd(a, _mm512_set1_pd(n));
#else
  for (double& x : a) x = n;
#endif
  std::printf("small frame: local %% 64 = %lu\n", static_cast<unsigned long>(reinterpret_cast<std::uintptr_t>(a) % 64));
  return a[5];
}

int main(int argc, char**) {
  double s = 0;
  for (int k = 0; k < 3; ++k) s += large_frame(argc + k) + small_frame(argc + k);
  std::printf("ok (%g)\n", s);
}
