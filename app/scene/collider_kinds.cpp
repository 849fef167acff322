#include "app/scene/collider_kinds.h"

#include <array>
#include <stdexcept>

#include "app/scene/kind_table.h"
#include "app/scene/model_file.h"
#include "app/scene/table_reader.h"
#include "sim/contact/colliders/box.h"
#include "sim/contact/colliders/elevator.h"
#include "sim/contact/colliders/mesh.h"
#include "sim/contact/colliders/plane.h"
#include "sim/contact/colliders/sphere.h"

namespace wobble {
namespace {

// plane: an infinite static plane, drawn as a finite textured square of its `size` centred on its `point`.
std::unique_ptr<Collider> readPlane(TableReader& r, const std::string& name, const ContactParams& contact,
                                    ColliderLook& look) {
  const Vec3 normal = r.vec3("normal", Vec3::UnitY());
  if (normal.norm() == 0) r.fail("normal", "must not be zero");
  auto plane = std::make_unique<PlaneCollider>(name, contact, r.vec3("point", Vec3::Zero()), normal);
  look.plane_size = r.number("size", look.plane_size, Range::positive());  // drawn extent: the renderer's only
  return plane;
}

void readPlaneLook(TableReader& r, ColliderLook& look) {
  look.texture_scale = r.number("texture_scale", look.texture_scale, Range::positive());
}

DrawnShape drawPlane(const Collider& c, const ColliderLook& look, double) {
  const auto& plane = static_cast<const PlaneCollider&>(c);
  return DrawnQuad{plane.point(), plane.normal(), look.plane_size, look.texture_scale};
}

// sphere: a solid ball, static or moving at constant velocity.
std::unique_ptr<Collider> readSphere(TableReader& r, const std::string& name, const ContactParams& contact,
                                     ColliderLook&) {
  const Vec3 center = r.vec3("center", Vec3::Zero());
  const double radius = r.number("radius", 1, Range::positive());
  return std::make_unique<SphereCollider>(name, contact, center, radius, r.vec3("velocity", Vec3::Zero()));
}

// Drawn inset by the contact tolerance: a cloth resting on the sphere keeps its particles within epsilon of it, but
// its flat triangles cut the chords between them (sagitta s^2 / 8r, ~3.5 mm on the default cloth) and would let the
// exact sphere show through as specks.
DrawnShape drawSphere(const Collider& c, const ColliderLook&, double t) {
  const auto& sphere = static_cast<const SphereCollider&>(c);
  return DrawnSphere{sphere.center(t), sphere.radius() - sphere.contact().epsilon};
}

// elevator: a square platform on a time schedule, drawn as a slab whose top face is the platform top.
std::unique_ptr<Collider> readElevator(TableReader& r, const std::string& name, const ContactParams& contact,
                                       ColliderLook&) {
  ElevatorSchedule s;
  s.start = r.vec3("start", s.start);
  s.accel = r.number("accel", s.accel, Range::nonNegative());
  s.travel = r.number("travel", s.travel, Range::positive());
  s.pause = r.number("pause", s.pause, Range::nonNegative());
  const double size = r.number("size", 5, Range::positive());
  return std::make_unique<ElevatorCollider>(name, contact, s, size, r.number("thickness", 0.25, Range::positive()));
}

DrawnShape drawElevator(const Collider& c, const ColliderLook&, double t) {
  const auto& e = static_cast<const ElevatorCollider&>(c);
  return DrawnBox{e.topCenter(t) - Vec3(0, e.thickness() / 2, 0), Vec3(e.size(), e.thickness(), e.size())};
}

// box: a static axis-aligned box, drawn as itself.
std::unique_ptr<Collider> readBox(TableReader& r, const std::string& name, const ContactParams& contact,
                                  ColliderLook&) {
  const Vec3 center = r.vec3("center", Vec3::Zero());
  const Vec3 size = r.vec3("size", Vec3::Ones());
  if ((size.array() <= 0).any()) r.fail("size", "each extent must be > 0");
  return std::make_unique<BoxCollider>(name, contact, center, size);
}

DrawnShape drawBox(const Collider& c, const ColliderLook&, double) {
  const auto& box = static_cast<const BoxCollider&>(c);
  return DrawnBox{box.center(), box.size()};
}

// mesh: the user's triangle mesh, placed like a mesh jelly; open meshes (a plate) allowed; moving at `velocity`.
std::unique_ptr<Collider> readMesh(TableReader& r, const std::string& name, const ContactParams& contact,
                                   ColliderLook&) {
  const ModelMesh model = readModelKey(r, false);
  const Placement place = readPlacement(r, Vec3::Zero(), model);
  const Eigen::Matrix3d rotation = place.rotation();
  std::vector<Vec3> points;
  for (const Vec3& p : localPoints(model, place.scale)) points.push_back(place.center + rotation * p);
  return std::make_unique<MeshCollider>(name, contact, std::move(points), model.triangles,
                                        r.vec3("velocity", Vec3::Zero()));
}

DrawnShape drawMesh(const Collider& c, const ColliderLook&, double t) {
  const auto& mesh = static_cast<const MeshCollider&>(c);
  return DrawnMesh{mesh.offset(t), &mesh.points(), &mesh.triangles()};
}

const std::array kKinds{
    ColliderKind{"plane", Vec3(1, 1, 1), "checker", false, readPlane, readPlaneLook, drawPlane},
    ColliderKind{"sphere", Vec3(0.75, 0.72, 0.68), "none", true, readSphere, nullptr, drawSphere},
    ColliderKind{"elevator", Vec3(0.55, 0.6, 0.7), "none", true, readElevator, nullptr, drawElevator},
    ColliderKind{"box", Vec3(0.6, 0.45, 0.3), "wood", false, readBox, nullptr, drawBox},
    ColliderKind{"mesh", Vec3(0.85, 0.85, 0.82), "none", true, readMesh, nullptr, drawMesh},
};

}  // namespace

std::span<const ColliderKind> colliderKinds() { return kKinds; }

std::vector<std::string> colliderTypes() { return kindTypes(colliderKinds()); }

const ColliderKind& colliderKind(std::string_view type) { return findKind(colliderKinds(), type, "collider"); }

}  // namespace wobble
