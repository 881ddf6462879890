// The path tracer of Polychronakis et al. 2021 (sections 3.1-3.2, 4): scene validation, camera path, BVH against
// brute force, emitter table, OBJ loading, and GPU renders against values known in closed form
// (emitters and a diffuse plane seen directly, a glass slab's transmittance, a clear glass object
// under a uniform sky), next-event estimation against BSDF sampling alone, and determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "core/input_error.h"
#include "core/prng.h"
#include "renderer/path_tracing/bvh.h"
#include "renderer/path_tracing/courtyard_scene.h"
#include "renderer/path_tracing/gpu_scene.h"
#include "renderer/path_tracing/mesh_builder.h"
#include "renderer/path_tracing/obj_scene.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/path_tracing/ray_intersection.h"
#include "tests/renderer/vulkan_test_fixture.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

using test::VulkanTest;

const std::string kMeshes = std::string(FOVLAB_SOURCE_DIR) + "/tests/fixtures/meshes/";

// The InputError message of f(), or "" when it throws none.
template <typename F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

CameraPath still_camera(glm::vec3 eye, glm::vec3 target, float fov_deg, glm::vec3 up = {0.0f, 1.0f, 0.0f}) {
  CameraPath camera;
  camera.keyframes = {{0.0, eye, target}};
  camera.vertical_fov_deg = fov_deg;
  camera.up = up;
  return camera;
}

// A large emissive wall filling the view.
PathScene emitter_wall(glm::vec3 radiance) {
  PathScene scene;
  const uint32_t light = add_material(scene, {MaterialKind::emissive, radiance, 1.0f});
  add_quad_facing(scene, light, {-10, -10, -2}, {10, -10, -2}, {10, 10, -2}, {-10, 10, -2}, {0, 0, 1});
  scene.camera = still_camera({0, 0, 0}, {0, 0, -1}, 40.0f);
  return scene;
}

// A wide Lambertian plane under a uniform sky, seen from above.
PathScene plane_under_sky(glm::vec3 albedo, glm::vec3 sky) {
  PathScene scene;
  const uint32_t ground = add_material(scene, {MaterialKind::lambertian, albedo, 1.5f});
  add_quad_facing(scene, ground, {-1000, 0, -1000}, {1000, 0, -1000}, {1000, 0, 1000}, {-1000, 0, 1000}, {0, 1, 0});
  scene.sky_radiance = sky;
  scene.camera = still_camera({0, 1, 0}, {0, 0, 0}, 60.0f, {0, 0, -1});
  return scene;
}

// A closed box of coloured Lambertian walls with a small emissive quad under its ceiling; the camera
// inside. No sky reaches in, so every light path starts at the quad.
PathScene lit_box() {
  PathScene scene;
  const uint32_t white = add_material(scene, {MaterialKind::lambertian, {0.75f, 0.75f, 0.75f}, 1.5f});
  const uint32_t red = add_material(scene, {MaterialKind::lambertian, {0.7f, 0.15f, 0.1f}, 1.5f});
  const uint32_t light = add_material(scene, {MaterialKind::emissive, {12.0f, 11.0f, 9.0f}, 1.0f});
  add_box(scene, white, {-1, -1, -1}, {1, 1, 1});
  add_box(scene, red, {-0.6f, -1, -0.5f}, {-0.1f, -0.2f, 0.0f});
  add_quad_facing(scene, light, {-0.3f, 0.98f, -0.3f}, {0.3f, 0.98f, -0.3f}, {0.3f, 0.98f, 0.3f}, {-0.3f, 0.98f, 0.3f},
                  {0, -1, 0});
  scene.sky_radiance = {5.0f, 5.0f, 5.0f};  // unreachable from inside
  scene.camera = still_camera({0, 0, 0.95f}, {0, -0.1f, -1}, 70.0f);
  return scene;
}

PathTraceSettings small(int spp, int bounces, uint32_t seed = 1) {
  PathTraceSettings settings;
  settings.width_px = 32;
  settings.height_px = 24;
  settings.samples_per_pixel = spp;
  settings.max_bounces = bounces;
  settings.seed = seed;
  return settings;
}

glm::dvec3 mean_rgb(const Image& image) {
  glm::dvec3 sum(0.0);
  for (size_t p = 0; p < image.pixel_count(); ++p)
    for (int c = 0; c < 3; ++c) sum[c] += image.pixels[p * 3 + size_t(c)];
  return sum / double(image.pixel_count());
}

// Mean squared difference per value between two images of one size.
double mean_squared_difference(const Image& a, const Image& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    sum += double(a.pixels[i] - b.pixels[i]) * double(a.pixels[i] - b.pixels[i]);
  return sum / double(a.pixels.size());
}

// ---- CPU: scenes, camera, BVH, emitters, OBJ -----------------------------------------------------

TEST(PathScene, InvalidScenesAreInputErrors) {
  EXPECT_NE(input_error([] { validate(PathScene{}); }).find("no triangles: expected at least one"), std::string::npos);

  PathScene bad_material = emitter_wall({1, 1, 1});
  bad_material.material_per_triangle[1] = 5;
  EXPECT_NE(input_error([&] { validate(bad_material); }).find("triangle 1: material 5: expected less than 1"),
            std::string::npos);

  PathScene bad_index = emitter_wall({1, 1, 1});
  bad_index.indices[2] = 99;
  EXPECT_NE(input_error([&] { validate(bad_index); }).find("vertex index 99: expected less than 6"), std::string::npos);

  PathScene bad_camera = emitter_wall({1, 1, 1});
  bad_camera.camera.keyframes[0].eye.x = NAN;
  EXPECT_NE(input_error([&] { validate(bad_camera); }).find("keyframe 0: expected a finite time, eye and target"),
            std::string::npos);
  bad_camera.camera.keyframes.clear();
  EXPECT_NE(input_error([&] { validate(bad_camera); }).find("expected at least one keyframe"), std::string::npos);

  PathScene bad_glass = emitter_wall({1, 1, 1});
  bad_glass.materials[0] = {MaterialKind::glass, {1, 1, 1}, 0.5f};
  EXPECT_NE(input_error([&] { validate(bad_glass); }).find("index of refraction"), std::string::npos);

  PathScene bad_albedo = plane_under_sky({1.5f, 0.5f, 0.5f}, {1, 1, 1});
  EXPECT_NE(input_error([&] { validate(bad_albedo); }).find("expected an albedo or tint of at most 1"),
            std::string::npos);

  EXPECT_NO_THROW(validate(courtyard_scene()));
}

TEST(PathScene, InvalidSettingsAreInputErrors) {
  PathTraceSettings settings = small(4, 4);
  EXPECT_NO_THROW(validate(settings));
  settings.width_px = 0;
  EXPECT_EQ(input_error([&] { validate(settings); }), "path tracing width 0: expected 1 to 16384");
  settings = small(0, 4);
  EXPECT_EQ(input_error([&] { validate(settings); }), "path tracing samples per pixel 0: expected 1 to 65536");
  settings = small(4, -1);
  EXPECT_EQ(input_error([&] { validate(settings); }), "path tracing max bounces -1: expected 0 to 1024");
  settings = small(4, 4);
  settings.time_s = INFINITY;
  EXPECT_NE(input_error([&] { validate(settings); }).find("expected a finite number"), std::string::npos);
}

TEST(PathScene, CameraPathPassesThroughItsKeyframesAndHoldsOutsideThem) {
  const CameraPath path = courtyard_scene().camera;
  for (const CameraKeyframe& key : path.keyframes) {
    const CameraPose pose = camera_pose_at(path, key.time_s);
    EXPECT_LT(glm::length(pose.eye - key.eye), 1e-5f);
    EXPECT_LT(glm::length(pose.target - key.target), 1e-5f);
  }
  EXPECT_EQ(camera_pose_at(path, -3.0).eye, path.keyframes.front().eye);
  EXPECT_EQ(camera_pose_at(path, 100.0).eye, path.keyframes.back().eye);
  // Smooth: a frame at 60 Hz moves the eye by a few centimetres, never a jump.
  for (double t = 0.0; t < 12.0; t += 1.0 / 60.0)
    EXPECT_LT(glm::length(camera_pose_at(path, t + 1.0 / 60.0).eye - camera_pose_at(path, t).eye), 0.1f) << t;
}

// Random triangles in a unit cube (many overlaps) plus the courtyard: the BVH finds the same
// nearest triangle at the same distance as testing every triangle.
TEST(PathTracingBvh, AgreesWithBruteForceOnRandomRays) {
  PathScene soup;
  const uint32_t material = add_material(soup, {});
  Pcg32 random(7);
  auto point = [&] { return glm::vec3(float(random.uniform()), float(random.uniform()), float(random.uniform())); };
  for (int t = 0; t < 1500; ++t) {
    const glm::vec3 a = point();
    add_triangle_facing(soup, material, a, a + 0.1f * (point() - 0.5f), a + 0.1f * (point() - 0.5f), {0, 0, 1});
  }
  soup.camera = still_camera({0, 0, 3}, {0, 0, 0}, 60.0f);

  for (const PathScene& scene : {soup, courtyard_scene()}) {
    const Bvh bvh = build_bvh(scene);
    // Every triangle in exactly one leaf; children inside their parents.
    std::vector<int> seen(scene.triangle_count(), 0);
    for (size_t n = 0; n < bvh.nodes.size(); ++n) {
      const BvhNode& node = bvh.nodes[n];
      if (node.triangle_count > 0) {
        EXPECT_LE(node.triangle_count, 4u);
        for (uint32_t i = node.left_or_first; i < node.left_or_first + node.triangle_count; ++i)
          ++seen[bvh.triangle_order[i]];
        continue;
      }
      for (uint32_t child = node.left_or_first; child <= node.left_or_first + 1; ++child) {
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(bvh.nodes[child].bounds_min, node.bounds_min)));
        EXPECT_TRUE(glm::all(glm::lessThanEqual(bvh.nodes[child].bounds_max, node.bounds_max)));
      }
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int count) { return count == 1; }));
    EXPECT_LE(bvh.depth, kBvhMaxDepth);

    const glm::vec3 lo = bvh.nodes[0].bounds_min, hi = bvh.nodes[0].bounds_max;
    int hits = 0;
    for (int r = 0; r < 1500; ++r) {
      Ray ray;
      ray.origin = lo + (hi - lo) * point();
      ray.direction = glm::normalize(2.0f * point() - 1.0f);
      if (r % 10 == 0) ray.direction = {0.0f, -1.0f, 0.0f};  // axis-aligned: zero direction components
      const auto expected = intersect_brute_force(scene, ray, INFINITY);
      const auto actual = intersect_bvh(scene, bvh, ray, INFINITY);
      ASSERT_EQ(expected.has_value(), actual.has_value()) << "ray " << r;
      if (!expected) continue;
      ++hits;
      EXPECT_EQ(expected->triangle, actual->triangle) << "ray " << r;
      EXPECT_EQ(expected->distance, actual->distance) << "ray " << r;
    }
    EXPECT_GT(hits, 250);
  }
}

TEST(PathTracingBvh, EmitterTableIsANormalisedAreaTimesPowerDistribution) {
  PathScene scene = lit_box();
  const uint32_t dim = add_material(scene, {MaterialKind::emissive, {1.0f, 1.0f, 1.0f}, 1.0f});
  add_quad_facing(scene, dim, {-0.9f, -0.98f, -0.9f}, {0.9f, -0.98f, -0.9f}, {0.9f, -0.98f, 0.9f},
                  {-0.9f, -0.98f, 0.9f}, {0, 1, 0});
  add_triangle_facing(scene, dim, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0});  // zero area: never picked
  const PackedScene packed = pack_scene(scene, build_bvh(scene));
  ASSERT_EQ(packed.emitters.size(), 4u);
  EXPECT_EQ(packed.emitters.back().cdf, 1.0f);
  double total = 0.0, bright = 0.0;
  float previous = 0.0f;
  for (const GpuEmitter& emitter : packed.emitters) {
    EXPECT_GT(emitter.cdf, previous);
    previous = emitter.cdf;
    const GpuTriangle& triangle = packed.triangles[emitter.slot];
    const double probability =
        triangle.light_pdf_per_area * 0.5 * glm::length(glm::cross(triangle.edge1, triangle.edge2));
    total += probability;
    if (triangle.material == 2) bright += probability;
  }
  EXPECT_NEAR(total, 1.0, 1e-5);
  // Light 0.36 m^2 of mean radiance 32/3 against 3.24 m^2 of radiance 1.
  EXPECT_NEAR(bright, 0.36 * 32.0 / 3.0 / (0.36 * 32.0 / 3.0 + 3.24), 1e-5);
  for (const GpuTriangle& triangle : packed.triangles) {
    if (scene.materials[triangle.material].kind != MaterialKind::emissive) {
      EXPECT_EQ(triangle.light_pdf_per_area, 0.0f);
    }
  }
}

TEST(ObjScene, LoadsTrianglesAndMaterialsFromObjAndMtl) {
  ObjLoadReport report;
  const PathScene scene = load_obj_scene(kMeshes + "three_materials.obj", &report);
  EXPECT_EQ(scene.triangle_count(), 8u);
  EXPECT_EQ(report.triangles, 8u);
  EXPECT_EQ(report.dropped_degenerate_triangles, 0u);
  EXPECT_EQ(report.triangles_without_material, 1u);
  ASSERT_EQ(scene.materials.size(), 5u);  // floor, green_glass, lamp, unused_red, default
  EXPECT_EQ(scene.materials[0].kind, MaterialKind::lambertian);
  EXPECT_EQ(scene.materials[0].colour, glm::vec3(0.8f));
  EXPECT_EQ(scene.materials[1].kind, MaterialKind::glass);
  EXPECT_EQ(scene.materials[1].colour, glm::vec3(0.5f, 0.9f, 0.6f));
  EXPECT_FLOAT_EQ(scene.materials[1].index_of_refraction, 1.45f);
  EXPECT_EQ(scene.materials[2].kind, MaterialKind::emissive);
  EXPECT_EQ(scene.materials[2].colour, glm::vec3(4.0f, 3.0f, 2.0f));
  EXPECT_EQ(scene.materials[3].colour, glm::vec3(0.9f, 0.1f, 0.1f));
  EXPECT_EQ(scene.materials[4].colour, glm::vec3(0.5f));
  const std::vector<uint32_t> expected_materials = {4, 0, 0, 1, 1, 1, 1, 2};
  EXPECT_EQ(scene.material_per_triangle, expected_materials);
  // The lamp's relative indices -6 -4 -5 name vertices 9, 11, 10.
  EXPECT_EQ(scene.positions[scene.indices[21]], glm::vec3(-0.5f, 2.0f, -0.5f));
  EXPECT_EQ(scene.positions[scene.indices[22]], glm::vec3(0.0f, 2.0f, 0.5f));
  EXPECT_EQ(scene.positions[scene.indices[23]], glm::vec3(0.5f, 2.0f, -0.5f));
  EXPECT_EQ(scene.camera.keyframes.size(), 3u);
  EXPECT_NO_THROW(validate(scene));
  EXPECT_NE(report.summary().find("8 triangles"), std::string::npos);
}

TEST(ObjScene, ZeroAreaTrianglesAreDroppedAndCounted) {
  ObjLoadReport report;
  const PathScene scene = load_obj_scene(kMeshes + "degenerate_triangles.obj", &report);
  EXPECT_EQ(scene.triangle_count(), 1u);
  EXPECT_EQ(report.dropped_degenerate_triangles, 2u);
  EXPECT_NE(report.summary().find("2 zero-area triangles dropped"), std::string::npos);

  testing::TempDir dir;
  const std::string only_degenerate = dir.write("flat.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n");
  EXPECT_NE(
      input_error([&] { load_obj_scene(only_degenerate); }).find("flat.obj: no triangles (1 of zero area dropped)"),
      std::string::npos);
}

TEST(ObjScene, BadFilesAreInputErrorsNamingFileAndLine) {
  EXPECT_NE(input_error([] {
              load_obj_scene(kMeshes + "non_finite_vertex.obj");
            }).find("non_finite_vertex.obj:5: expected three finite vertex coordinates"),
            std::string::npos);
  EXPECT_NE(input_error([] {
              load_obj_scene(kMeshes + "face_out_of_range.obj");
            }).find("face_out_of_range.obj:6: vertex index out of range: expected 1 to 3"),
            std::string::npos);
  const std::string missing_library = input_error([] { load_obj_scene(kMeshes + "missing_library.obj"); });
  EXPECT_NE(missing_library.find("missing_library.obj:3: material library"), std::string::npos) << missing_library;
  EXPECT_NE(missing_library.find("no_such_library.mtl"), std::string::npos);
  EXPECT_NE(input_error([] {
              load_obj_scene(kMeshes + "no_such_mesh.obj");
            }).find("no_such_mesh.obj: cannot open (No such file or directory): expected an OBJ mesh"),
            std::string::npos);
}

TEST(ObjScene, OnlyRegularFilesWithinTheCapsAreRead) {
  testing::TempDir dir;
  EXPECT_EQ(input_error([&] { load_obj_scene(dir.path()); }),
            dir.path().string() + ": not a regular file (a directory): expected an OBJ mesh");
  EXPECT_EQ(input_error([] { load_obj_scene("/dev/zero"); }),
            "/dev/zero: not a regular file (a character device): expected an OBJ mesh");
  // A folder named as the material library was read as an empty library: materials silently lost.
  std::filesystem::create_directories(dir.path() / "library.mtl");
  const std::string with_folder =
      dir.write("folder_library.obj", "mtllib library.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(input_error([&] { load_obj_scene(with_folder); }),
            with_folder + ":1: material library: " + (dir.path() / "library.mtl").string() +
                ": not a regular file (a directory): expected an MTL material library");
  // One byte over the cap (sparse: nothing is written), refused from its size.
  const std::string big = dir.write("big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  std::filesystem::resize_file(big, kMaxObjBytes + 1);
  EXPECT_EQ(input_error([&] { load_obj_scene(big); }), big + ": larger than 512 MiB (" +
                                                           std::to_string(kMaxObjBytes + 1) +
                                                           " bytes): expected an OBJ mesh of at most 512 MiB");
}

TEST(ObjScene, AByteOrderMarkIsIgnoredNotTheFirstLineLost) {
  // tinyobjloader read "\xEF\xBB\xBFv" as an unknown keyword: the first vertex was dropped and the
  // face's index 3 was out of range.
  testing::TempDir dir;
  const std::string bom = "\xEF\xBB\xBF";
  dir.write("bom.mtl", bom + "newmtl red\nKd 0.9 0.1 0.1\n");  // the same in an MTL file: "newmtl red" was lost
  ObjLoadReport report;
  const PathScene scene = load_obj_scene(
      dir.write("bom.obj", bom + "v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib bom.mtl\nusemtl red\nf 1 2 3\n"), &report);
  ASSERT_EQ(scene.triangle_count(), 1u);
  EXPECT_EQ(scene.positions.at(0), glm::vec3(0.0f));
  EXPECT_EQ(report.triangles_without_material, 0u);
  EXPECT_EQ(scene.materials.at(scene.material_per_triangle.at(0)).colour, glm::vec3(0.9f, 0.1f, 0.1f));
}

TEST(ObjScene, SkinWeightLinesAreIgnored) {
  // tinyobjloader refused a negative joint id ("Failed parse `vw' line") and converted 1e30 to int
  // (undefined behaviour; tests/fuzz/corpus/obj/finding-obj-skin-weight-joint-out-of-int-range.obj).
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const auto no_library = [](const std::string& name) -> std::string { throw InputError(name + ": none"); };
  for (const char* weights : {"vw 1 -1 0.5\n", "vw 0 1e30 1\n", "  vw\t2 0 0.25 1 0.75\n"}) {
    const PathScene scene = parse_obj_scene(weights + triangle, "weights.obj", no_library);
    EXPECT_EQ(scene.triangle_count(), 1u) << weights;
  }
  // Lines keep their numbers: the bad vertex after a skin-weight line is on line 2.
  EXPECT_EQ(input_error([&] { parse_obj_scene("vw 1 -1 0.5\nv 0 nan 0\n", "weights.obj", no_library); }),
            "weights.obj:2: expected three finite vertex coordinates");
}

TEST(ObjScene, ParsesTextWithLibrariesFromTheCaller) {
  const std::string obj = "# a comment\nmtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n";
  const auto library = [](const std::string& name) -> std::string {
    if (name != "lib.mtl") throw InputError(name + ": no such library");
    return "newmtl lamp\nKe 2 2 2\n";
  };
  const PathScene scene = parse_obj_scene(obj, "text.obj", library);
  ASSERT_EQ(scene.triangle_count(), 1u);
  EXPECT_EQ(scene.materials.at(scene.material_per_triangle.at(0)).kind, MaterialKind::emissive);
  EXPECT_EQ(input_error([&] { parse_obj_scene("mtllib other.mtl\n", "text.obj", library); }),
            "text.obj:1: material library: other.mtl: no such library");
  // What validate() refuses in the scene made names the file too (a bounding box too large for
  // float: the camera's distance is infinite).
  EXPECT_EQ(input_error([&] {
              parse_obj_scene("v 3e38 3e38 3e38\nv -3e38 -3e38 3e38\nv 3e38 -3e38 -3e38\nf 1 2 3\n", "huge.obj",
                              library);
            }).rfind("huge.obj: scene camera", 0),
            0u);
}

// ---- GPU -----------------------------------------------------------------------------------------

TEST_F(VulkanTest, PathTracedEmitterSeenDirectlyGivesItsRadiance) {
  const glm::vec3 radiance(0.75f, 2.5f, 10.0f);
  PathTracer tracer(context(), emitter_wall(radiance));
  const PathTraceResult result = tracer.render(small(3, 4));
  EXPECT_EQ(result.samples, 32u * 24u * 3u);
  ASSERT_EQ(result.image.channels, 3);
  for (size_t p = 0; p < result.image.pixel_count(); ++p)
    for (int c = 0; c < 3; ++c) ASSERT_FLOAT_EQ(result.image.pixels[p * 3 + size_t(c)], radiance[c]);
}

// Every ray leaving the plane goes to the sky, so each sample is exactly albedo x sky; with no
// bounce allowed the plane is black.
TEST_F(VulkanTest, PathTracedDiffusePlaneUnderSkyReadsAlbedoTimesSky) {
  const glm::vec3 albedo(0.2f, 0.5f, 0.8f), sky(1.0f, 2.0f, 0.5f);
  PathTracer tracer(context(), plane_under_sky(albedo, sky));
  const Image lit = tracer.render(small(4, 3)).image;
  for (size_t p = 0; p < lit.pixel_count(); ++p)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(lit.pixels[p * 3 + size_t(c)], albedo[c] * sky[c], 1e-6);
  const Image direct_only = tracer.render(small(2, 0)).image;
  for (float value : direct_only.pixels) ASSERT_EQ(value, 0.0f);
}

// Next-event estimation changes the noise, not the mean: the image mean agrees with BSDF sampling
// alone (16x the samples) within 3 % (about 5 standard errors of the latter; converged, the two
// agree within 0.3 %), and its pixels are less noisy.
TEST_F(VulkanTest, PathTracingWithNextEventEstimationAgreesWithBsdfSamplingAlone) {
  PathTracer tracer(context(), lit_box());
  EXPECT_EQ(tracer.emitter_count(), 2u);
  PathTraceSettings nee = small(16, 5);
  PathTraceSettings brute = small(256, 5, 2);
  brute.next_event_estimation = false;
  const Image with_nee = tracer.render(nee).image;
  const Image without = tracer.render(brute).image;
  const glm::dvec3 a = mean_rgb(with_nee), b = mean_rgb(without);
  for (int c = 0; c < 3; ++c) {
    EXPECT_GT(a[c], 0.05);
    EXPECT_NEAR(a[c], b[c], 0.03 * b[c]) << "channel " << c;
  }
  nee.seed = 3;
  brute.seed = 4;
  brute.samples_per_pixel = 16;
  const double nee_noise = mean_squared_difference(with_nee, tracer.render(nee).image);
  const double brute_noise = mean_squared_difference(tracer.render(brute).image, tracer.render(small(16, 5, 5)).image);
  EXPECT_LT(nee_noise, 0.5 * brute_noise);
}

// A slab of glass (IOR 1.5) between the camera and an emitter of radiance 1, seen at near-normal
// incidence: it transmits T^2 * sum R^2k = (1 - R) / (1 + R) with R = 0.04, the tint (per
// refraction) squared; the light reflected back comes from a black sky.
TEST_F(VulkanTest, PathTracedGlassSlabTransmitsWhatFresnelSays) {
  for (float tint : {1.0f, 0.5f}) {
    PathScene scene = emitter_wall({1.0f, 1.0f, 1.0f});
    const uint32_t glass = add_material(scene, {MaterialKind::glass, glm::vec3(tint), 1.5f});
    add_box(scene, glass, {-5, -5, -1.1f}, {5, 5, -0.9f});
    scene.camera = still_camera({0, 0, 5}, {0, 0, 0}, 10.0f);
    PathTracer tracer(context(), scene);
    const double reflectance = 0.04;
    const double expected = tint * tint * (1.0 - reflectance) / (1.0 + reflectance);
    const glm::dvec3 mean = mean_rgb(tracer.render(small(8, 32)).image);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], expected, 0.015 * tint) << "tint " << tint;
  }
}

// Clear glass neither creates nor loses light: under a uniform sky (nothing else in the scene) every
// path ends in the sky with throughput 1, unless it runs out of bounces.
TEST_F(VulkanTest, PathTracedClearGlassUnderUniformSkyKeepsTheSkyRadiance) {
  PathScene scene;
  const uint32_t glass = add_material(scene, {MaterialKind::glass, glm::vec3(1.0f), 1.5f});
  add_faceted_sphere(scene, glass, {0, 0, 0}, 1.0f, 8, 12);
  add_prism(scene, glass, {1.2f, -0.8f, 0.5f}, 0.5f, 1.2f, 5);
  scene.sky_radiance = {1.0f, 1.0f, 1.0f};
  scene.camera = still_camera({0, 0.5f, 4}, {0.3f, 0, 0}, 45.0f);
  PathTracer tracer(context(), scene);
  const glm::dvec3 mean = mean_rgb(tracer.render(small(4, 32)).image);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(mean[c], 1.0 + 1e-6);
    EXPECT_GT(mean[c], 0.995);
  }
}

TEST_F(VulkanTest, PathTracingIsDeterministicForASeed) {
  PathTracer tracer(context(), courtyard_scene());
  PathTraceSettings settings = small(2, 6);
  settings.time_s = 3.0;
  const PathTraceResult first = tracer.render(settings);
  const PathTraceResult second = tracer.render(settings);
  EXPECT_EQ(first.image.pixels, second.image.pixels);
  for (float value : first.image.pixels) ASSERT_TRUE(std::isfinite(value) && value >= 0.0f);
  const glm::dvec3 mean = mean_rgb(first.image);
  EXPECT_GT(mean.x + mean.y + mean.z, 0.1) << "the courtyard is lit";
  settings.seed = 2;
  EXPECT_NE(tracer.render(settings).image.pixels, first.image.pixels);
  settings.seed = 1;
  settings.time_s = 9.0;
  EXPECT_NE(tracer.render(settings).image.pixels, first.image.pixels) << "the camera moves";
}

TEST_F(VulkanTest, PathTracerRefusesBadScenesSettingsAndCameras) {
  PathScene scene = emitter_wall({1, 1, 1});
  scene.material_per_triangle[0] = 3;
  EXPECT_NE(input_error([&] { PathTracer tracer(context(), scene); }).find("material 3: expected less than 1"),
            std::string::npos);
  PathTracer tracer(context(), plane_under_sky({0.5f, 0.5f, 0.5f}, {1, 1, 1}));
  EXPECT_EQ(input_error([&] { tracer.render(small(1, 0)); }), "");
  PathTraceSettings settings = small(1, 1);
  settings.height_px = 20000;
  EXPECT_EQ(input_error([&] { tracer.render(settings); }), "path tracing height 20000: expected 1 to 16384");
  PathTracer straight_down(context(), [] {
    PathScene s = plane_under_sky({0.5f, 0.5f, 0.5f}, {1, 1, 1});
    s.camera.up = {0, 1, 0};
    return s;
  }());
  EXPECT_NE(input_error([&] { straight_down.render(small(1, 1)); }).find("parallel to the up vector"),
            std::string::npos);
}

TEST_F(VulkanTest, PathTracesAnObjScene) {
  ObjLoadReport report;
  PathTracer tracer(context(), load_obj_scene(kMeshes + "three_materials.obj", &report));
  EXPECT_EQ(tracer.triangle_count(), 8u);
  EXPECT_EQ(tracer.emitter_count(), 1u);
  const PathTraceResult result = tracer.render(small(2, 4));
  for (float value : result.image.pixels) ASSERT_TRUE(std::isfinite(value) && value >= 0.0f);
  EXPECT_EQ(result.batches, 1);
}

}  // namespace
}  // namespace fovlab
