# FFD_ARCH, the instruction set every object is compiled for (-march).
#
# The default, native, tunes for the build machine: AVX-512 where it has it, the CPU's own
# tuning. Its outputs differ between CPU models in the last bits (Eigen's packet width
# changes the order of its sums, and the tuning where GCC contracts a*b+c into an FMA).
# x86-64-v3 (AVX2, FMA, BMI2: x86 CPUs since about 2015) gives one binary whatever CPU
# built it, so the same inputs give the same output bytes on every such machine; it is
# the build that byte-compares the seam goldens (tests/seam_cli_test.cpp). On an AVX-512
# CPU it is slower: the B-spline move step on 1M points took 370 ms against native's 97.
# An empty FFD_ARCH is the compiler's default: a portable x86-64 binary, no AVX, no FMA.
#
# x86-64-v3 on a machine that cannot run it (another architecture, or an x86 CPU without
# AVX2) falls back to native, with a message.
if(FFD_ARCH STREQUAL "x86-64-v3")
  set(_ffd_arch_ok FALSE)
  if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
    file(WRITE "${CMAKE_BINARY_DIR}/ffd_arch_check.cpp" [=[
int main() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                 __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("popcnt")
             ? 0
             : 1;
}
]=])
    try_run(_ffd_arch_run _ffd_arch_compiled "${CMAKE_BINARY_DIR}/ffd_arch_check"
            "${CMAKE_BINARY_DIR}/ffd_arch_check.cpp")
    if(_ffd_arch_compiled AND _ffd_arch_run EQUAL 0)
      set(_ffd_arch_ok TRUE)
    endif()
  endif()
  if(NOT _ffd_arch_ok)
    message(STATUS "FFD_ARCH: this machine cannot run x86-64-v3 code; building for -march=native")
    set(FFD_ARCH "native")
  endif()
endif()
