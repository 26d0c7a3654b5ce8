// Chapter 12 tests of light transport through materials, against what is known exactly: the
// white furnace (a sphere that neither absorbs nor emits is invisible under a uniform sky),
// the single-scattering albedo of a rough conductor without compensation (its loss, by
// quadrature), an interface of index 1 that is no interface, and the stiff cases: nearly
// smooth lobes, glass inside glass, grazing rays. The BSDFs themselves are tested in
// test_ch12_bsdf.cpp; the scenes and loaders in test_ch12_scenes.cpp.
#include <cmath>

#include "rt_catch.h"

#include "energy_compensation.h"
#include "material_cases.h"
#include "material_report.h"

using namespace rt;
using namespace rt::ch12;
using namespace rt::ch12::testing;

namespace {

const Extent k_small{32, 24};

// The mean radiance over the image and its standard error: under a sky of 1, an invisible
// sphere gives 1.
MeanAndError furnace_statistics(const Material& material, int samples, unsigned long long& bad,
                                const MaterialOptions& options = {},
                                const CameraSpec& camera = sphere_camera()) {
  const MaterialScene scene = make_sphere_in_sky(material, 4, 1.0f);
  const Render r = render(scene, Backend::cpu, camera, k_small, samples, {}, options);
  bad = r.non_finite;
  return pixel_statistics(r.mean);
}

} // namespace

TEST_CASE("furnace: a smooth glass sphere is invisible (radiance 1 within 0.5%)", "[ch12]") {
  unsigned long long bad = 1;
  const MeanAndError s = furnace_statistics(named_material("glass", 0.0f), 128, bad);
  CAPTURE(s.mean, s.standard_error);
  CHECK(bad == 0);
  // Within 0.5%, not within a few standard errors: a path that leaves the glass after Russian
  // roulette carries 1 / survival, and such rare bright samples make the mean of a few
  // thousand pixels fall short of 1 more often than not (0.27% here at 128 samples).
  CHECK(std::abs(s.mean - 1.0) < 0.005);
}

TEST_CASE("furnace from inside the glass: radiance is eta^2 times the sky's", "[ch12]") {
  // Radiance crossing into a denser medium is compressed into a narrower cone: inside glass of
  // index eta under a sky of 1 it is eta^2 (the 1 / eta^2 of every refraction, undone). Seen
  // from outside, the two crossings cancel and a renderer without the factor passes; from
  // inside, one crossing is left, and only the factor gives eta^2.
  for (const float ior : {1.5f, 1.33f}) {
    CAPTURE(ior);
    Material glass = named_material("glass");
    glass.ior = ior;
    const MaterialScene scene = make_sphere_in_sky(glass, 4, 1.0f);
    CameraSpec inside = sphere_camera();
    inside.eye = {0.0, 0.0, 0.0};
    inside.target = {0.0, 0.0, -1.0};
    inside.fov_degrees = 60.0;
    const Render r = render(scene, Backend::cpu, inside, k_small, 64);
    const MeanAndError s = pixel_statistics(r.mean);
    CAPTURE(s.mean, s.standard_error);
    CHECK(r.non_finite == 0);
    CHECK(std::abs(s.mean / (double(ior) * ior) - 1.0) < 0.005);
  }
}

TEST_CASE("furnace: a slightly rough glass sphere is invisible (radiance 1 within 0.5%)",
          "[ch12]") {
  // Rougher glass loses light the way a rough metal does (light that the microfacets send
  // back into one another), and is scaled to keep it (test_ch12_glass.cpp tests every
  // roughness, with and without the scale); these two lose almost nothing to begin with.
  for (const float roughness : {0.05f, 0.1f}) {
    CAPTURE(roughness);
    unsigned long long bad = 1;
    const MeanAndError s =
        furnace_statistics(named_material("rough-glass", roughness), 64, bad);
    CAPTURE(s.mean, s.standard_error);
    CHECK(bad == 0);
    CHECK(std::abs(s.mean - 1.0) < 0.005);
  }
}

TEST_CASE("furnace: a white rough metal with compensation is invisible within 1%", "[ch12]") {
  for (const float roughness : {0.0f, 0.1f, 0.3f, 0.5f, 0.7f, 1.0f}) {
    CAPTURE(roughness);
    unsigned long long bad = 1;
    const MeanAndError s =
        furnace_statistics(named_material("white-metal", roughness), 32, bad);
    CAPTURE(s.mean, s.standard_error);
    CHECK(bad == 0);
    CHECK(std::abs(s.mean - 1.0) < 0.01);
  }
}

TEST_CASE("furnace: without compensation a rough metal keeps its single-scattering albedo",
          "[ch12]") {
  // Seen head-on, the sphere returns E(1, alpha) of the sky: one bounce, whose rays all leave
  // the convex sphere, those the microfacets send below the horizon lost.
  for (const float roughness : {0.3f, 0.6f, 1.0f}) {
    const double alpha = double(roughness) * roughness;
    const double expected = single_scattering_albedo(alpha, 1.0);
    CAPTURE(roughness, expected);
    unsigned long long bad = 1;
    const MeanAndError s = furnace_statistics(named_material("white-metal", roughness), 64, bad,
                                              {.compensation = false}, sphere_centre_camera());
    CAPTURE(s.mean, s.standard_error);
    CHECK(bad == 0);
    CHECK(expected < 0.999); // there is a loss to see
    CHECK(std::abs(s.mean - expected) < 0.005);
    // and with compensation it is gone
    const MeanAndError c = furnace_statistics(named_material("white-metal", roughness), 64, bad,
                                              {}, sphere_centre_camera());
    CHECK(std::abs(c.mean - 1.0) < 0.01);
  }
}

TEST_CASE("an index of refraction of exactly 1 is no interface: every pixel is the sky",
          "[ch12]") {
  for (const float roughness : {0.0f, 0.5f}) {
    Material m = named_material("glass", roughness);
    m.ior = 1.0f;
    const MaterialScene scene = make_sphere_in_sky(m, 3, 1.0f);
    const Render r = render(scene, Backend::cpu, sphere_camera(), k_small, 4);
    CAPTURE(roughness);
    CHECK(r.non_finite == 0);
    for (const Vec3f& p : r.mean) {
      CHECK(p.x == Approx(1.0f).epsilon(1e-6));
      CHECK(p.z == Approx(1.0f).epsilon(1e-6));
    }
  }
}

TEST_CASE("glass seen through glass, and a sphere inside a sphere, stay invisible", "[ch12]") {
  MaterialScene scene = make_sphere_in_sky(named_material("glass", 0.0f), 4, 1.0f);
  MaterialScene inner = make_sphere_in_sky(named_material("glass", 0.0f), 3, 1.0f);
  ch04::Mesh& mesh = scene.path.mesh;
  const int base = static_cast<int>(mesh.vertices.size());
  for (const Vec3f& v : inner.path.mesh.vertices) mesh.vertices.push_back(v * 0.5f);
  for (const ch04::IndexedTriangle& t : inner.path.mesh.triangles) {
    mesh.triangles.push_back({t.v0 + base, t.v1 + base, t.v2 + base});
    scene.path.material.push_back(0);
  }
  scene.path.lights = ch11::build_light_table(scene.path);
  const Render r = render(scene, Backend::cpu, sphere_camera(), k_small, 64);
  const MeanAndError s = pixel_statistics(r.mean);
  CAPTURE(s.mean, s.standard_error);
  CHECK(r.non_finite == 0);
  CHECK(std::abs(s.mean - 1.0) < 0.005);
}

TEST_CASE("a nearly smooth lobe (alpha 1e-4) converges to the smooth material's image",
          "[ch12]") {
  for (const char* name : {"gold", "glass"}) {
    CAPTURE(name);
    const CameraSpec camera = roughness_series_camera();
    const auto image = [&](float roughness, unsigned first) {
      MaterialScene scene = make_roughness_series(named_material(name, 0.0f));
      for (Material& m : scene.materials)
        if (m.model != MaterialModel::lambertian) m.roughness = roughness;
      return render(scene, Backend::cpu, camera, {40, 24}, 32, {}, {}, first);
    };
    const Render smooth = image(0.0f, 0), smooth_again = image(0.0f, 1000);
    const Render nearly = image(0.01f, 0); // alpha = roughness^2 = 1e-4
    CHECK(nearly.non_finite == 0);
    const double noise = rms(smooth.mean, smooth_again.mean);
    const double difference = rms(smooth.mean, nearly.mean);
    CAPTURE(noise, difference);
    CHECK(difference < 1.5 * noise);
  }
}

TEST_CASE("grazing rays and every material: no NaN or infinity reaches a pixel", "[ch12]") {
  // The camera just above the sphere's top: its rays meet the sphere at every angle down to
  // grazing along the silhouette.
  CameraSpec camera = sphere_camera();
  camera.eye = {0.0, 1.0 + 1e-4, 4.0};
  camera.target = {0.0, 1.0, 0.0};
  for (const char* name : {"white", "glass", "rough-glass", "white-metal", "plastic", "gold"})
    for (const float roughness : {0.0f, 0.01f, 0.3f, 1.0f}) {
      CAPTURE(name, roughness);
      const MaterialScene scene = make_sphere_in_sky(named_material(name, roughness), 3, 1.0f);
      const Render r = render(scene, Backend::cpu, camera, {16, 16}, 8);
      CHECK(r.non_finite == 0);
    }
}

TEST_CASE("megakernel, persistent and wavefront give the same sums, every kernel kind",
          "[ch12]") {
  const MaterialScene scene = make_roughness_series(named_material("plastic", 0.0f));
  const CameraSpec camera = roughness_series_camera();
  const Render first = render(scene, Backend::cpu, camera, {24, 16}, 4);
  for (const PathVariant variant :
       {PathVariant::megakernel, PathVariant::persistent, PathVariant::wavefront})
    for (const ch06::KernelKind kind :
         {ch06::KernelKind::specialised, ch06::KernelKind::all_features}) {
      CAPTURE(ch11::to_string(variant), int(kind));
      const Render r = render(scene, Backend::cpu, camera, {24, 16}, 4,
                              {variant, kind, ch11::Strategy::mis});
      CHECK(ch11::testing::same_sums(r.sums, first.sums));
    }
}

TEST_CASE("every strategy converges to the same image of the material room", "[ch12][slow]") {
  const MaterialScene scene = load_material_scene(k_room_gltf);
  const CameraSpec camera = *scene.camera;
  const Extent extent{24, 18};
  const Render mis = render(scene, Backend::cpu, camera, extent, 256);
  const MeanAndError m = pixel_statistics(mis.mean);
  for (const ch11::Strategy strategy : {ch11::Strategy::light, ch11::Strategy::bsdf}) {
    CAPTURE(ch11::to_string(strategy));
    const Render r = render(scene, Backend::cpu, camera, extent, 256,
                            {PathVariant::megakernel, ch06::KernelKind::specialised, strategy});
    const MeanAndError s = pixel_statistics(r.mean);
    CAPTURE(m.mean, s.mean, m.standard_error, s.standard_error);
    CHECK(r.non_finite == 0);
    CHECK(std::abs(s.mean - m.mean) < 0.03 * m.mean);
  }
}

TEST_CASE("the material room as OBJ/MTL and as glTF renders the same image", "[ch12]") {
  const MaterialScene gltf = load_material_scene(k_room_gltf);
  const MaterialScene obj = load_material_scene(k_room_obj);
  REQUIRE(gltf.camera.has_value());
  const Extent extent{32, 24};
  const Render a = render(gltf, Backend::cpu, *gltf.camera, extent, 16);
  const Render again = render(gltf, Backend::cpu, *gltf.camera, extent, 16, {}, {}, 5000);
  const Render b = render(obj, Backend::cpu, *gltf.camera, extent, 16);
  const double noise = rms(a.mean, again.mean), difference = rms(a.mean, b.mean);
  CAPTURE(noise, difference);
  CHECK(difference < 0.5 * noise); // the same paths through the same surfaces
  const MeanAndError sa = pixel_statistics(a.mean), sb = pixel_statistics(b.mean);
  CHECK(std::abs(sa.mean - sb.mean) < 0.01 * sa.mean);
}

namespace {

// A square lamp of side 2 at height 1, facing down, over a grey floor; its emission texture
// (when `textured`) is black on one half and white on the other, split across the middle.
MaterialScene textured_lamp_scene(bool textured) {
  MaterialScene scene;
  ch11::PathScene& s = scene.path;
  const auto add_quad = [&](Vec3f a, Vec3f b, Vec3f c, Vec3f d, int material) {
    const int base = static_cast<int>(s.mesh.vertices.size());
    s.mesh.vertices.insert(s.mesh.vertices.end(), {a, b, c, d});
    s.mesh.triangles.push_back({base, base + 1, base + 2});
    s.mesh.triangles.push_back({base, base + 2, base + 3});
    s.material.insert(s.material.end(), {material, material});
  };
  Material floor;
  floor.base_color = {0.5f, 0.5f, 0.5f};
  Material lamp;
  lamp.base_color = {0.0f, 0.0f, 0.0f};
  lamp.emission = {4.0f, 4.0f, 4.0f};
  if (textured) {
    lamp.emission_texture = 0;
    scene.textures.push_back(make_texture("half black, half white", 2, 1,
                                          {{0, 0, 0, 255}, {255, 255, 255, 255}}, true));
  }
  for (const Material& m : {floor, lamp}) {
    scene.materials.push_back(m);
    s.materials.push_back({m.base_color, m.emission});
  }
  add_quad({-20, 0, 20}, {20, 0, 20}, {20, 0, -20}, {-20, 0, -20}, 0); // faces up
  add_quad({-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}, 1);         // faces down
  scene.uv.resize(s.mesh.triangles.size());
  scene.uv[2] = {Vec2f{0, 0}, Vec2f{1, 0}, Vec2f{1, 1}}; // u runs along x on the lamp
  scene.uv[3] = {Vec2f{0, 0}, Vec2f{1, 1}, Vec2f{0, 1}};
  s.lights = ch11::build_light_table(s);
  check_material_scene(scene, "the textured lamp");
  return scene;
}

} // namespace

TEST_CASE("an emission texture: next-event estimation and bounces see the same lamp",
          "[ch12]") {
  // Right below the lamp's middle the floor sees the black and the white half alike: with the
  // texture it receives half of what the untextured lamp gives it, by either strategy.
  CameraSpec camera; // between lamp and floor, looking straight down at a small patch
  camera.eye = {0.0, 0.5, 0.0};
  camera.target = {0.0, 0.0, 0.0};
  camera.up = {0.0, 0.0, -1.0};
  camera.fov_degrees = 2.0;
  const MaterialScene plain = textured_lamp_scene(false), textured = textured_lamp_scene(true);
  for (const ch11::Strategy strategy : {ch11::Strategy::light, ch11::Strategy::bsdf}) {
    CAPTURE(ch11::to_string(strategy));
    const RenderSettings settings{PathVariant::megakernel, ch06::KernelKind::specialised,
                                  strategy};
    const MeanAndError full =
        pixel_statistics(render(plain, Backend::cpu, camera, {16, 16}, 64, settings).mean);
    const Render half = render(textured, Backend::cpu, camera, {16, 16}, 64, settings);
    const MeanAndError h = pixel_statistics(half.mean);
    CAPTURE(full.mean, h.mean, full.standard_error, h.standard_error);
    CHECK(half.non_finite == 0);
    CHECK(std::abs(h.mean / full.mean - 0.5) < 0.03);
  }
}
