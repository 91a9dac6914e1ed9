#include "mpm/colliders/domain_walls.h"

#include "mpm/colliders/contact.h"

namespace nsf {

void apply_domain_walls(const SimSettings& s, int i, int j, int k, const Vec3i& dims, Vec3& v) {
  const int idx[3] = {i, j, k};
  const ContactRule rule{s.wall_contact, s.wall_friction};
  // A node in a corner belongs to several walls; each face's rule is applied in turn.
  for (int a = 0; a < 3; ++a) {
    Vec3 n = Vec3::Zero();
    if (idx[a] < s.wall_nodes) {
      n[a] = 1.0;  // the wall's outward normal points into the domain
    } else if (idx[a] >= dims[a] - s.wall_nodes) {
      n[a] = -1.0;
    } else {
      continue;
    }
    apply_contact(rule, n, Vec3::Zero(), v);
  }
}

}  // namespace nsf
