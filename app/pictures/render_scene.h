// RenderScene: a wobble SceneFile as a render::Scene. Each body's surface mesh (topology once, positions and normals
// every frame), each collider the scene names as the shape its kind draws (collider_kinds.h; the moving ones again at
// every frame), the sun and the sky, or the environment map that replaces both.
// Materials come from the bodies' and colliders' look keys (render_config.h) and the bodies' textures.
#pragma once
#include <span>
#include <vector>

#include "app/scene/scene_file.h"
#include "render/scene.h"
#include "sim/surface.h"

namespace wobble {

struct ColliderKind;

class RenderScene {
 public:
  // Loads the body textures and the environment map the scene names (and no others). Throws std::runtime_error if a
  // texture cannot be read, InputError if the environment map cannot.
  explicit RenderScene(const SceneFile& scene);

  // Surfaces of every body, in scene.system->bodies() order, and the time for the moving colliders; commits.
  // Throws std::invalid_argument (from the renderer) on a non-finite vertex.
  void update(double t, std::span<const SurfaceFrame> surfaces);
  // Motion blur: the scene posed at each of the shutter's instants (app/run/shutter.h), open to close: every body's
  // surfaces at times[j] are poses[j], the moving colliders are drawn at those times. One instant: a still frame.
  void update(std::span<const double> times, std::span<const std::vector<SurfaceFrame>> poses);

  const render::Scene& scene() const { return scene_; }

 private:
  struct MovingCollider {
    render::ShapeId shape;
    const Collider* collider;
    const ColliderKind* kind;  // draws it
    ColliderLook look;
  };

  render::Scene scene_;
  std::vector<render::ShapeId> body_shapes_;
  std::vector<MovingCollider> moving_;
};

}  // namespace wobble
