#include "sim/contact/ccd/impact_zones.h"

#include <Eigen/Dense>

namespace wobble::collision {

int ImpactZones::rigidify(const Candidates& round, const std::vector<Contact>& hits, double h) {
  std::vector<char> touched(inv_mass_.size(), 0);
  for (const Contact& c : hits) {  // the particles of the pair's vertices
    const auto& s = round.info(nodes_, c.pair).stencil;
    const int first = nodes_.node_particle[nodes_.node_start[s.vertex[0]]];
    for (const int k : s.vertex)
      for (int j = nodes_.node_start[k]; j < nodes_.node_start[k + 1]; ++j) {
        merge(first, nodes_.node_particle[j]);
        touched[nodes_.node_particle[j]] = 1;
      }
  }
  // Every member of a touched zone: zones grow across rounds, so gather them from the roots.
  std::vector<char> root_touched(inv_mass_.size(), 0);
  for (const int p : nodes_.pass_particles)
    if (touched[p]) root_touched[find(p)] = 1;
  std::vector<std::vector<int>> members(inv_mass_.size());
  for (const int p : nodes_.pass_particles)
    if (root_touched[find(p)]) members[find(p)].push_back(p);
  int largest = 0;
  for (const auto& zone : members) {
    if (zone.empty()) continue;
    largest = std::max(largest, int(zone.size()));
    bool pinned = false;
    double mass = 0;
    Vec3 center = Vec3::Zero(), momentum = Vec3::Zero();
    for (const int p : zone) {
      if (inv_mass_[p] == 0) {
        pinned = true;
        continue;
      }
      const double m = 1 / inv_mass_[p];
      mass += m;
      center += m * particle(motion_.xs, p);
      momentum += m * particle(motion_.vbar, p);
    }
    Vec3 velocity = Vec3::Zero(), omega = Vec3::Zero();
    if (!pinned) {
      center /= mass;
      velocity = momentum / mass;
      Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
      Vec3 angular = Vec3::Zero();
      for (const int p : zone) {
        const double m = 1 / inv_mass_[p];
        const Vec3 r = particle(motion_.xs, p) - center;
        angular += m * r.cross(particle(motion_.vbar, p) - velocity);
        inertia += m * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
      }
      omega = inertia.completeOrthogonalDecomposition().solve(angular);  // collinear zones: the least-norm spin
    }
    for (const int p : zone) {
      particle(motion_.vbar, p) =
          pinned ? Vec3::Zero() : Vec3(velocity + omega.cross(particle(motion_.xs, p) - center));
      particle(motion_.xe, p) = particle(motion_.xs, p) + h * particle(motion_.vbar, p);
      motion_.changed[p] = 1;
    }
    motion_.refreshNodes(nodes_, zone);
  }
  return largest;
}

}  // namespace wobble::collision
