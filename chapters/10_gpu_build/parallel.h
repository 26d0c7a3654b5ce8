// Chapter 10: the tools every pass of the GPU build is written with, all from common/:
// rt::for_each_index (rt/launch.h) runs one RT_HD function per item, as a CUDA kernel or on CPU
// threads; rt::BackendArray holds a pass's data in device or host memory, whichever the backend
// reads; rt::BackendStopwatch (rt/timer.h) takes a build's time as the benchmark protocol does,
// CUDA events around the kernels (the sort included, transfers not) on the GPU, wall time on
// the CPU. Only .cu files include this header: the GPU side needs nvcc.
#pragma once

#include <cstddef>

#include "bvh_trace.h"
#include "rt/backend.h"
#include "rt/backend_array.h"
#include "rt/cuda_check.h"
#include "rt/device_buffer.h"
#include "rt/launch.h"
#include "rt/timer.h"
