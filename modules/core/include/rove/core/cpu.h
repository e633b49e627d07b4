#pragma once
/// \file
/// Which instruction-set kernels rove runs. A few hot loops (the k-nearest
/// set of the KD-tree, GICP's linearization) have an AVX2 version next to
/// the baseline x86-64 (SSE2) one; each is chosen at run time, once per
/// call, from avx2_enabled(). Both versions do the same arithmetic in the
/// same order lane by lane, so results are the same bit for bit whichever
/// runs (the tests check this).
///
/// The AVX2 kernels run when the processor has AVX2 and the environment
/// variable ROVE_MAX_ISA is not `sse2` when the process first asks
/// (ROVE_MAX_ISA=sse2 measures the baseline on an AVX2 machine). On other
/// architectures and compilers only the portable versions exist.

/// 1 where rove compiles its AVX2 kernels (x86-64 with GCC or Clang),
/// else 0: the guard around every AVX2 kernel and its dispatch.
#if defined(__x86_64__) && defined(__GNUC__)
#define ROVE_AVX2_KERNELS 1
#else
#define ROVE_AVX2_KERNELS 0
#endif

namespace rove {

/// True when rove's AVX2 kernels run (see the file comment).
bool avx2_enabled() noexcept;

namespace detail {

/// For tests and benchmarks: `on = false` makes every later call run the
/// baseline kernels; `on = true` restores AVX2 where the processor has it
/// (it cannot enable what the processor lacks). Not synchronized with
/// searches running on other threads.
void set_avx2_enabled(bool on) noexcept;

/// True when the processor has AVX2, whatever the setting.
bool cpu_has_avx2() noexcept;

}  // namespace detail
}  // namespace rove
