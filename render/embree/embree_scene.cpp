// RTCScene ownership and single-ray queries (see embree_scene.h).
#include "render/embree/embree_scene.h"

#include <stdexcept>

namespace wobble::render {

namespace {

void fillRay(const Ray& r, RTCRay& ray) {
  ray.org_x = r.origin.x();
  ray.org_y = r.origin.y();
  ray.org_z = r.origin.z();
  ray.dir_x = r.direction.x();
  ray.dir_y = r.direction.y();
  ray.dir_z = r.direction.z();
  ray.tnear = r.tnear;
  ray.tfar = r.tfar;
  ray.time = r.time;
  ray.mask = 0xFFFFFFFFu;
  ray.id = 0;
  ray.flags = 0;
}

}  // namespace

EmbreeScene::EmbreeScene(RTCDevice device) {
  scene_ = rtcNewScene(device);
  if (!scene_) throw std::runtime_error("Embree: cannot create a scene");
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_DYNAMIC);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_LOW);
}

EmbreeScene::~EmbreeScene() { rtcReleaseScene(scene_); }

void EmbreeScene::attach(RTCGeometry geometry, unsigned id) { rtcAttachGeometryByID(scene_, geometry, id); }

void EmbreeScene::commit() { rtcCommitScene(scene_); }

RTCRayHit EmbreeScene::intersect(const Ray& r) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit;
  fillRay(r, rayhit.ray);
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rayhit);
  return rayhit;
}

bool EmbreeScene::occluded(const Ray& r) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  fillRay(r, ray);
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0;  // Embree sets tfar to -inf when it finds a blocker
}

}  // namespace wobble::render
