#pragma once
/// \file
/// Opt-in tuning of the BLAS and OpenMP runtime under SuiteSparse CHOLMOD
/// (the supernodal back-end of optimize() for dense 3D graphs). Both settings
/// are process-wide, so no rove library function makes them: a program calls
/// these once, early, before it starts threads of its own (the `rove` command
/// line and the benchmarks do). Without them CHOLMOD and its BLAS run with
/// their own defaults; results are the same, only the speed differs.

namespace rove {

/// Chooses OpenBLAS's kernels from the instruction sets this CPU reports, by
/// setting OPENBLAS_CORETYPE (SkylakeX with AVX-512 F/BW/DQ/VL, Haswell with
/// AVX2 + FMA) unless the variable is already set. OpenBLAS reads it when it
/// loads, with CHOLMOD, on the first dense problem; a model newer than the
/// installed OpenBLAS knows otherwise gets its SSE3 kernels (Debian 12's
/// 0.3.21 on a 5th-generation Xeon: sphere2500 factorizes 1.45x slower).
/// Not thread-safe: it calls setenv(); call it before any other thread runs.
void configure_blas_for_this_cpu();

/// Caps the threads of CHOLMOD's OpenMP regions at `num_threads` (≥ 1), in
/// the OpenMP runtime CHOLMOD is linked to: with 1 every region is made
/// inactive, with more the runtime may use up to that many. The setting is
/// applied once, when CHOLMOD is loaded (now, if it already is), and holds
/// for the rest of the process. CHOLMOD 3.x otherwise forks the thread count
/// it was compiled with (4 in Debian's build) for every large supernode:
/// 25-30 % more CPU time on sphere2500 with 2 cores. Throws InvalidArgument
/// for num_threads < 1. Call it before optimizations run on other threads.
void tune_blas_threads(int num_threads);

}  // namespace rove
