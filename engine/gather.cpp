// Force gather: each block sums the forces of its own sub-contacts, found through a
// block -> sub-contact index, so no two threads write the same block (no atomics, and
// the summation order, hence the result, is the same for any thread count).
#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {

namespace {

// Counting sort of (sub-contact, side) entries by block; entry 2i is side a, 2i+1 side b.
void build_gather_index(const Model& m, State& s) {
  const SubContacts& c = s.contacts;
  const int nb = m.block_count;
  const int n = static_cast<int>(c.size());
  s.block_contact_begin.assign(nb + 1, 0);
  for (int i = 0; i < n; ++i) {
    ++s.block_contact_begin[c.block_a[i] + 1];
    ++s.block_contact_begin[c.block_b[i] + 1];
  }
  for (int b = 0; b < nb; ++b) s.block_contact_begin[b + 1] += s.block_contact_begin[b];
  s.block_contact.resize(2 * static_cast<std::size_t>(n));
  s.block_contact_cursor.assign(s.block_contact_begin.begin(), s.block_contact_begin.end() - 1);
  for (int i = 0; i < n; ++i) {
    s.block_contact[s.block_contact_cursor[c.block_a[i]]++] = 2 * i;
    s.block_contact[s.block_contact_cursor[c.block_b[i]]++] = 2 * i + 1;
  }
  s.gather_index_valid = true;
}

}  // namespace

double gather_forces(const Model& m, State& s) {
  const SubContacts& c = s.contacts;
  const int nb = m.block_count;
  // The index changes only when the narrowphase regroups the sub-contacts.
  if (!s.gather_index_valid) build_gather_index(m, s);

  parallel_for(nb, [&](std::ptrdiff_t b) {
    Vec3 f = Vec3::Zero(), t = Vec3::Zero();
    for (int q = s.block_contact_begin[b]; q < s.block_contact_begin[b + 1]; ++q) {
      const int entry = s.block_contact[q];
      const int i = entry >> 1;
      const Vec3 fi = (entry & 1) ? c.force_n[i] : Vec3(-c.force_n[i]);
      f += fi;
      t += (c.point[i] - s.position[b]).cross(fi);
    }
    s.force[b] = f + s.applied_force[b];
    s.torque[b] = t + s.applied_torque[b];
  });

  // Power the prescribed blocks put in: minus the power of the contact forces on them.
  double power = 0.0;
  for (int b = 0; b < nb; ++b)
    if (m.motion[b] == Motion::prescribed)
      power -= (s.force[b] - s.applied_force[b]).dot(s.velocity[b]) +
               (s.torque[b] - s.applied_torque[b]).dot(s.angular_velocity[b]);
  return power;
}

}  // namespace ishibashi
