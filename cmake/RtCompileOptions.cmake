# Compile options shared by every target of the course (an interface target, rt::options).
add_library(rt_options INTERFACE)
add_library(rt::options ALIAS rt_options)

target_compile_options(rt_options INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow>
  # Extended lambdas let one __host__ __device__ lambda serve both backends.
  $<$<COMPILE_LANGUAGE:CUDA>:--extended-lambda --expt-relaxed-constexpr>
  $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra>
  # Double precision in device code is a choice, never an accident.
  $<$<COMPILE_LANGUAGE:CUDA>:-Xptxas=--warn-on-double-precision-use>
  $<$<AND:$<COMPILE_LANGUAGE:CUDA>,$<NOT:$<CONFIG:Debug>>>:-lineinfo>)

# The CPU backend's instruction set, for all host code: by default this machine's own, so that
# the loops written for vector units get them (chapter 09's CPU traversal tests eight child
# boxes per AVX instruction) and the explicit FMAs of the watertight test become instructions
# instead of calls. -ffp-contract=off keeps every result the same bit for bit as without it:
# given FMA instructions, GCC would otherwise fuse a * b + c in C++ wherever it likes.
# nvcc's host compiler gets the same two flags (device code keeps nvcc's own rules): the CPU
# code of the .cu files (chapter 11's CPU backend) is the same inline code as the C++ files',
# compiled the same way, so one program never holds two versions of one inline function.
# Set it empty (-DRT_CPU_ARCH=) for programs that run on any x86-64.
set(RT_CPU_ARCH "native" CACHE STRING "-march for all host code (empty: the compiler's default)")
if(RT_CPU_ARCH)
  target_compile_options(rt_options INTERFACE
    $<$<COMPILE_LANGUAGE:CXX>:-march=${RT_CPU_ARCH} -ffp-contract=off>
    # One -Xcompiler per flag: nvcc splits its value at commas.
    $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-march=${RT_CPU_ARCH} -Xcompiler=-ffp-contract=off>)
endif()

if(RT_SANITIZE)
  set(_rt_san -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
  target_compile_options(rt_options INTERFACE
    $<$<COMPILE_LANGUAGE:CXX>:${_rt_san}>
    # nvcc splits -Xcompiler values at commas, so each flag gets its own -Xcompiler.
    "$<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-fsanitize=address;-Xcompiler=-fsanitize=undefined>"
    "$<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-fno-omit-frame-pointer;-Xcompiler=-fno-sanitize-recover=all>")
  target_link_options(rt_options INTERFACE ${_rt_san})
endif()
