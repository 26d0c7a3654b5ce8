// Chapter 08: each memory path as a tracer for chapter 07's benchmark runner, so one run times
// every path on the same rays and checks each against chapter 07's hits bit for bit: the same
// tree and traversal, read through other load instructions, must give the same answers.
#pragma once

#include <vector>

#include "memory_paths.h"
#include "tracer.h"

namespace rt::ch08 {

// The paths of `paths` that run on the scene's backend, each a tracer named after its path;
// with `camera_in_kernel`, on the GPU also the kept path making the primary rays in the kernel
// itself, with the camera and the tree as kernel parameters or in __constant__ memory. Each
// scene's trees are packed (and uploaded) once, shared by its tracers.
ch07::TracerMaker memory_path_tracers(std::vector<MemoryPath> paths, bool camera_in_kernel);

// The kept path alone: what later chapters compare with.
ch07::TracerMaker kept_tracer();

} // namespace rt::ch08
