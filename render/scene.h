// Scene: everything the renderer draws: materials, shapes (simulator meshes, quads, boxes, spheres) and lights.
// It knows nothing about springs or bodies: the app converts its bodies and colliders into these calls.
//
// Life cycle per frame:
//   1. once:       add materials, then shapes (each returns an id), set `lights`
//   2. per frame:  updateMesh / updateBox / updateQuad / updateSphere for whatever moved, then commit()
//   3. render (renderer.h); intersect/occluded are safe to call from many threads between commits.
// Motion blur: the update...Motion calls give a shape several poses, at evenly spaced instants over the shutter, from
// its opening (ray time 0) to its closing (ray time 1, where the frame's own pose is: the last pose is the shape as
// shapeView and the exporters see it). A ray meets the shape as it is at the ray's time (Ray::time), linearly between
// the two poses around it: Embree's multi-segment motion blur (rtcSetGeometryTimeStepCount), and the hit's point,
// normals and texture derivatives interpolated alike here. One pose is a still shape, as the plain updates make.
// Every add/update validates its input and throws std::invalid_argument naming the shape (e.g. a NaN vertex),
// so a broken simulation frame is reported instead of rendered with triangles silently missing.
// Embree objects are owned here; the Scene is movable but not copyable.
#pragma once
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "render/bounds.h"
#include "render/hit.h"
#include "render/lights.h"
#include "render/material.h"
#include "render/mesh.h"
#include "render/ray.h"
#include "render/shapes.h"

namespace wobble::render {

using MaterialId = int;
using ShapeId = int;

class EmbreeDevice;
class EmbreeScene;
class EmbreeTriangleMesh;
class EmbreeSphere;

class Scene {
 public:
  Scene();
  ~Scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  MaterialId addMaterial(Material material);
  const Material& material(MaterialId id) const { return materials_.at(id); }

  // Topology (triangles, uv, vertex count) is fixed from here on.
  ShapeId addMesh(TriangleMesh mesh, MaterialId material);
  // New positions (same count and order) and optionally new normals (empty keeps flat/previous normals).
  void updateMesh(ShapeId id, std::span<const Eigen::Vector3f> positions,
                  std::span<const Eigen::Vector3f> normals = {});

  ShapeId addQuad(const std::string& name, const Quad& quad, MaterialId material);
  void updateQuad(ShapeId id, const Quad& quad);
  ShapeId addBox(const std::string& name, const Box& box, MaterialId material);
  void updateBox(ShapeId id, const Box& box);
  ShapeId addSphere(const std::string& name, const Sphere& sphere, MaterialId material);
  void updateSphere(ShapeId id, const Sphere& sphere);

  // Several poses over the shutter (at least one; the header's "Motion blur"). A mesh pose's normals may be empty
  // (flat or previous normals, as updateMesh) only if every pose's are.
  struct MeshPose {
    std::span<const Eigen::Vector3f> positions, normals;
  };
  void updateMeshMotion(ShapeId id, std::span<const MeshPose> poses);
  void updateQuadMotion(ShapeId id, std::span<const Quad> poses);
  void updateBoxMotion(ShapeId id, std::span<const Box> poses);
  void updateSphereMotion(ShapeId id, std::span<const Sphere> poses);
  // Whether the shape has more than one pose (moves while the shutter is open).
  bool moving(ShapeId id) const;

  // Builds the acceleration structure (rtcCommitScene). Needed after any add or update, before tracing.
  void commit();
  bool committed() const { return committed_; }

  Lights lights;

  // `leaving`: the shape the ray starts on, if any (a path's bounce and shadow rays). When the ray provably cannot
  // meet that shape again and misses the bounds of all the others, the answer is known without Embree: on the
  // slope scene that is most rays leaving the floor, which see only sky and sun past a small jelly.
  std::optional<SurfaceHit> intersect(const Ray& ray, ShapeId leaving = -1) const;
  bool occluded(const Ray& ray, ShapeId leaving = -1) const;
  // Whether the ray, leaving shape `leaving`, provably hits nothing: it heads away from that shape's plane (quad),
  // face planes (box) or centre (sphere, from outside), and misses every other shape's bounds. Always false for a
  // mesh (a body may fold back onto itself) and for leaving = -1.
  bool provablyMisses(const Ray& ray, ShapeId leaving) const;
  // Fills hit.dpdu and hit.dpdv (left zero by intersect(): only texture filtering needs them).
  void uvDerivatives(SurfaceHit& hit) const;

  std::size_t shapeCount() const { return shapes_.size(); }
  // The shape's box around every pose over the shutter, as of the last commit().
  const Bounds& bounds(ShapeId id) const;
  const std::string& shapeName(ShapeId id) const;
  // What a shape is, for exporters (scene_export.h): a triangle mesh (simulator meshes, quads and boxes) or an
  // analytic sphere, and its material.
  struct ShapeView {
    const std::string& name;
    const TriangleMesh* mesh;  // null for a sphere
    const Sphere* sphere;      // null for a mesh
    MaterialId material;
  };
  ShapeView shapeView(ShapeId id) const;
  std::size_t materialCount() const { return materials_.size(); }
  // The raw Embree scene, for benchmarks and experiments.
  RTCScene embreeScene() const;

 private:
  struct Shape;
  Shape& shape(ShapeId id, const char* expected_kind);
  ShapeId attach(std::unique_ptr<Shape> shape);
  // Quads and boxes: triangle meshes built from their parameters (Shape::set), alike on add and update.
  template <typename Shaped>
  ShapeId addShaped(const std::string& name, const Shaped& params, MaterialId material);
  template <typename Shaped>
  void updateShaped(ShapeId id, std::span<const Shaped> poses);

  std::unique_ptr<EmbreeDevice> device_;
  std::unique_ptr<EmbreeScene> rtc_;
  std::vector<Material> materials_;
  std::vector<std::unique_ptr<Shape>> shapes_;
  bool committed_ = false;
};

}  // namespace wobble::render
