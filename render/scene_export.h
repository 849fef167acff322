// exportScene: a committed Scene and a Camera written for other renderers (the Cycles comparison in bench/), so the
// same frame can be rendered elsewhere and each renderer's error measured against its own converged picture.
//   DIR/scene.obj    every triangle mesh (simulator meshes, quads, boxes) as an object named after its shape, with
//                    normals and UVs where it has them; world space, Y up, metres
//   DIR/scene.json   camera (position, look_at, up, vertical fov, resolution), suns (direction, irradiance, angular
//                    radius), area lights, sky (zenith, horizon, ground colours, up), analytic spheres (centre,
//                    radius), and per shape its material (colour, coat, ior, roughness, texture image); with an
//                    environment map, "environment" (its file as an absolute path, rotation_deg, strength), which
//                    replaces the sky
//   DIR/texture_<material>.png   each material's texture baked over UV [0, 1]^2 (sRGB, 1024 x 1024)
// Throws std::runtime_error naming the file when a file cannot be written.
#pragma once
#include <filesystem>

#include "image/image.h"
#include "render/camera.h"
#include "render/scene.h"

namespace wobble::render {

void exportScene(const Scene& scene, const Camera& camera, const std::filesystem::path& dir);

// A texture over one tile of UV, [0, 1]^2, as an sRGB image of size x size (row 0 at v = 1): what Blender's image
// texture reads where wobble evaluates a procedural one (the Cycles comparison).
image::Image8 bakeTexture(const Texture& texture, int size = 1024);
// The texture over the UV rectangle [lo, hi] as an sRGB image of width x height (row 0 at v = hi), each texel the
// texture's mean over its patch (evalFootprint): `wobble blend` bakes a collider's whole UV range, as wood is not
// periodic (each board its own tone and grain).
image::Image8 bakeTexture(const Texture& texture, const Eigen::Vector2f& lo, const Eigen::Vector2f& hi, int width,
                          int height);

}  // namespace wobble::render
