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

if(RT_SANITIZE)
  set(_rt_san -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
  target_compile_options(rt_options INTERFACE
    $<$<COMPILE_LANGUAGE:CXX>:${_rt_san}>
    # nvcc splits -Xcompiler values at commas, so each flag gets its own -Xcompiler.
    "$<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-fsanitize=address;-Xcompiler=-fsanitize=undefined>"
    "$<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-fno-omit-frame-pointer;-Xcompiler=-fno-sanitize-recover=all>")
  target_link_options(rt_options INTERFACE ${_rt_san})
endif()
