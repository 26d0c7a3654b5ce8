// Chapter 10: the moving scene's motion, written once on the scalar type. The host makes the
// reference scene with it in double (animation.cpp, moving_scene_at), the backend moves the
// vertices with it in float (moving_frames.cu), each frame.
#pragma once

#include <cmath>
#include <numbers>

#include "rt/hd.h"
#include "rt/vec.h"

namespace rt::ch10 {

// How far a waving model's vertices rise and fall.
inline constexpr float k_wave_height = 0.15f;

namespace motion {

// Sine and cosine in the scalar type: the C library's in double (the host's reference), sinf
// and cosf in float (CUDA's on the GPU), so that the float motion holds no double.
RT_HD inline float sine(float x) { return sinf(x); }
RT_HD inline float cosine(float x) { return cosf(x); }
inline double sine(double x) { return std::sin(x); }
inline double cosine(double x) { return std::cos(x); }

} // namespace motion

// [listing:torus_vertex]
// Vertex (i, j) of the torus around the y axis (i of `around` segments around it, j of
// `across` across its tube) at `time`: the tube's radius ripples in a wave that runs around
// it, so every vertex moves every frame, and by a different amount.
template <class T> RT_HD Vec3<T> torus_vertex(int i, int j, int around, int across, T time) {
  using motion::cosine, motion::sine;
  constexpr T pi = std::numbers::pi_v<T>;
  const T u = T(2) * pi * T(i) / T(around);
  const T v = T(2) * pi * T(j) / T(across);
  const T tube = T(0.55) * (T(1) + T(0.25) * sine(T(5) * u + T(3) * v - T(2) * time));
  const T ring = T(2) + tube * cosine(v);
  return {ring * cosine(u), tube * sine(v), ring * sine(u)};
}
// [/listing:torus_vertex]

// [listing:wave_height]
// A waving model's vertex (x, y, z) at `time`: its height lifted by a wave that runs across
// the floor, k_wave_height * sin(2 x + 1.5 z - 2 time).
template <class T> RT_HD T wave_height(T x, T y, T z, T time) {
  return y + T(k_wave_height) * motion::sine(T(2) * x + T(1.5) * z - T(2) * time);
}
// [/listing:wave_height]

// The centre of orbiting sphere k (0 to 3) at `time`: each on its own orbit around the
// torus, bobbing twice a turn.
template <class T> RT_HD Vec3<T> sphere_centre(int k, T time) {
  using motion::cosine, motion::sine;
  constexpr T pi = std::numbers::pi_v<T>;
  const T phase = time * (T(0.6) + T(0.15) * T(k)) + T(k) * pi / T(2);
  return {T(3.4) * cosine(phase), T(0.9) * sine(T(2) * phase), T(3.4) * sine(phase)};
}

} // namespace rt::ch10
