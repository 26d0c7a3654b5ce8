// Chapter 03: a scene of spheres, and the default one, built to show the stiff cases next to
// ordinary ones: a ground sphere of radius 1e5 seen from 1.5 units above it, and small moons
// hundreds to thousands of radii away.
#pragma once

#include "sphere.h"

namespace rt::ch03 {

struct Material {
  Vec3f colour;           // linear RGB in [0, 1]
  float reflectivity = 0; // share of the colour that comes from the mirror direction
  bool checkered = false; // a checkerboard on x, z (shows where hit points land)
};

// A handful of spheres, held by value: the whole scene travels to the GPU as a kernel
// argument, with no device allocation at all.
template <class T> struct SphereScene {
  static constexpr int k_max_spheres = 16;
  Sphere<T> spheres[k_max_spheres];
  Material materials[k_max_spheres];
  int count = 0;
  T square = T(1); // the checkerboard's square: grows with the scene's scale

  void add(Sphere<T> sphere, Material material) {
    spheres[count] = sphere;
    materials[count] = material;
    ++count;
  }
  // The same scene in another precision (the float64 reference of a float scene starts from
  // the float values).
  template <class U> SphereScene<U> as() const {
    SphereScene<U> out;
    for (int i = 0; i < count; ++i)
      out.add({spheres[i].centre.template as<U>(), static_cast<U>(spheres[i].radius)},
              materials[i]);
    out.square = static_cast<U>(square);
    return out;
  }
  // The same scene with every length multiplied by `factor`: the stiff cases of rounding at
  // another scale, with the same picture.
  SphereScene scaled(T factor) const {
    SphereScene out;
    for (int i = 0; i < count; ++i)
      out.add({spheres[i].centre * factor, spheres[i].radius * factor}, materials[i]);
    out.square = square * factor;
    return out;
  }
};

// The default scene: ground of radius 1e5 whose top is the plane y = 0, a mirror sphere, two
// coloured ones, and three moons at 300, 1 000 and 3 000 radii from the camera.
inline SphereScene<float> make_default_scene() {
  SphereScene<float> scene;
  scene.add({{0.0f, -1e5f, 0.0f}, 1e5f}, {{0.8f, 0.8f, 0.75f}, 0.0f, true});
  scene.add({{0.0f, 1.0f, 0.0f}, 1.0f}, {{0.9f, 0.9f, 0.9f}, 0.85f, false});
  scene.add({{-2.6f, 0.7f, -0.6f}, 0.7f}, {{0.85f, 0.25f, 0.2f}, 0.1f, false});
  scene.add({{2.3f, 0.5f, 0.8f}, 0.5f}, {{0.2f, 0.4f, 0.9f}, 0.1f, false});
  // Moons low in the sky, r/D = 1/300, 1/1 000 and 1/3 000 seen from the default eye.
  scene.add({{-1200.0f, 450.0f, -3000.0f}, 11.0f}, {{0.95f, 0.9f, 0.6f}, 0.0f, false});
  scene.add({{400.0f, 1200.0f, -1e4f}, 10.0f}, {{0.95f, 0.9f, 0.6f}, 0.0f, false});
  scene.add({{3000.0f, 2500.0f, -3e4f}, 10.0f}, {{0.95f, 0.9f, 0.6f}, 0.0f, false});
  return scene;
}

} // namespace rt::ch03
