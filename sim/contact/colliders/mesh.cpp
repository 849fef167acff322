#include "sim/contact/colliders/mesh.h"

#include <embree3/rtcore.h>

#include <limits>
#include <stdexcept>

#include "sim/bodies/model_mesh.h"

namespace wobble {

struct MeshCollider::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Embree() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

struct Closest {
  const MeshCollider* mesh;
  Vec3 x;  // the query point, in the mesh's frame at t = 0
  double distance2 = std::numeric_limits<double>::infinity();
  int triangle = -1;
  Vec3 point = Vec3::Zero();
};

// Embree calls this for each triangle whose box is within the query radius; shrinking the radius prunes the rest.
bool closestTriangle(RTCPointQueryFunctionArguments* args) {
  auto& c = *static_cast<Closest*>(args->userPtr);
  const auto& t = c.mesh->triangles()[args->primID];
  const auto& p = c.mesh->points();
  const Vec3 q = closestPointOnTriangle(c.x, p[t[0]], p[t[1]], p[t[2]]);
  const double d2 = (q - c.x).squaredNorm();
  if (!(d2 < c.distance2)) return false;
  c.distance2 = d2;
  c.triangle = static_cast<int>(args->primID);
  c.point = q;
  // float radius, rounded up so that Embree never prunes a box this triangle's distance would keep.
  args->query->radius = std::nextafter(static_cast<float>(std::sqrt(d2)), std::numeric_limits<float>::infinity());
  return true;
}

}  // namespace

MeshCollider::MeshCollider(std::string name, ContactParams contact, std::vector<Vec3> points,
                           std::vector<std::array<int, 3>> triangles, const Vec3& velocity)
    : Collider(std::move(name), contact),
      points_(std::move(points)),
      triangles_(std::move(triangles)),
      velocity_(velocity),
      embree_(std::make_unique<Embree>()) {
  for (const Vec3& p : points_) box_.extend(p);
  for (const auto& t : triangles_) {
    const Vec3 n = (points_[t[1]] - points_[t[0]]).cross(points_[t[2]] - points_[t[0]]);
    normals_.push_back(n.norm() > 0 ? Vec3(n.normalized()) : Vec3::UnitY());
  }
  embree_->device = rtcNewDevice(nullptr);
  if (!embree_->device) throw std::runtime_error("mesh collider '" + this->name() + "': cannot start Embree");
  embree_->scene = rtcNewScene(embree_->device);
  RTCGeometry geometry = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), points_.size()));
  for (std::size_t i = 0; i < points_.size(); ++i)
    for (int a = 0; a < 3; ++a) v[3 * i + a] = static_cast<float>(points_[i][a]);
  auto* index = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), triangles_.size()));
  for (std::size_t i = 0; i < triangles_.size(); ++i)
    for (int a = 0; a < 3; ++a) index[3 * i + a] = static_cast<unsigned>(triangles_[i][a]);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(embree_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(embree_->scene);
}

MeshCollider::~MeshCollider() = default;

std::optional<SurfacePoint> MeshCollider::query(double t, const Vec3& x) const {
  Closest c{this, x - offset(t)};
  RTCPointQuery q;
  q.x = static_cast<float>(c.x.x());
  q.y = static_cast<float>(c.x.y());
  q.z = static_cast<float>(c.x.z());
  q.radius = std::numeric_limits<float>::infinity();
  q.time = 0;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(embree_->scene, &q, &context, closestTriangle, &c);
  if (c.triangle < 0) return std::nullopt;
  const Vec3& face = normals_[c.triangle];
  const Vec3 away = c.x - c.point;
  const double len = away.norm();
  const double side = away.dot(face) >= 0 ? 1 : -1;
  const Vec3 normal = len > 1e-12 ? Vec3(side * away / len) : face;
  return SurfacePoint{side * len, normal, velocity_, Vec3::Zero()};
}

void MeshCollider::near(double t, const StateRef& x, double margin, std::vector<int>& out) const {
  out.clear();
  const int n = static_cast<int>(x.size() / 3);
  out.reserve(n);  // once: the list never reallocates while a body settles onto the collider
  const Vec3 lo = box_.min() + offset(t), hi = box_.max() + offset(t);
  const double reach2 = margin > 0 ? margin * margin : 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = particle(x, i);
    const double d2 = (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();  // to the box: 0 inside it
    if (d2 > reach2) continue;
    if (const auto s = query(t, p); s && s->distance < margin) out.push_back(i);
  }
}

bool MeshCollider::mayBeNear(double t, const Eigen::AlignedBox3d& box, double margin) const {
  // near() asks query() only within the margin of the mesh's bounding box.
  const Eigen::AlignedBox3d mesh = *bounds(t);
  const double reach = (margin > 0 ? margin : 0) + roundOffSlack(magnitude(box) + magnitude(mesh));
  return box.squaredExteriorDistance(mesh) <= reach * reach;
}

std::optional<Eigen::AlignedBox3d> MeshCollider::bounds(double t) const {
  return Eigen::AlignedBox3d(box_.min() + offset(t), box_.max() + offset(t));
}

}  // namespace wobble
