// EmbreeScene: owns an RTCScene and traces single rays. Embree API used here: rtcNewScene, rtcSetSceneFlags,
// rtcSetSceneBuildQuality, rtcAttachGeometryByID, rtcCommitScene, rtcInitIntersectContext, rtcIntersect1,
// rtcOccluded1, rtcReleaseScene.
//
// Flags: RTC_SCENE_FLAG_DYNAMIC (geometry changes every frame, so favour fast rebuilds) and
// RTC_SCENE_FLAG_ROBUST (watertight traversal: rays do not slip through the shared edges of the jelly's triangles).
#pragma once
#include <embree3/rtcore.h>

#include "render/ray.h"

namespace wobble::render {

class EmbreeScene {
 public:
  explicit EmbreeScene(RTCDevice device);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Attaches with an explicit id so geometry ids equal the caller's shape indices.
  void attach(RTCGeometry geometry, unsigned id);
  // Rebuilds the BVH after geometry commits. Not thread-safe with tracing: call between frames.
  void commit();

  // Nearest hit in [ray.tnear, ray.tfar]; hit.geomID is RTC_INVALID_GEOMETRY_ID when there is none.
  RTCRayHit intersect(const Ray& ray) const;
  // Whether anything lies in [ray.tnear, ray.tfar].
  bool occluded(const Ray& ray) const;

  RTCScene get() const { return scene_; }

 private:
  RTCScene scene_ = nullptr;
};

}  // namespace wobble::render
