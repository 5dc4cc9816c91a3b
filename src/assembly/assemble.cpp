#include "assembly/assemble.hpp"

#include <algorithm>
#include <cmath>

#include "core/parallel.hpp"

namespace rbpart {

namespace {

// Contacts or rows per task: enough to outweigh a task's cost (a contact's three rows take about a
// microsecond).
constexpr std::size_t kGrain = 256;

// The Jacobian block of a point constraint along direction d at offset r from the COM:
// d . (v + w x r) = d . v + (r x d) . w.
Vec6 point_jacobian(const Vec3& d, const Vec3& r) {
  Vec6 j;
  j << d, r.cross(d);
  return j;
}

Vec6 angular_jacobian(const Vec3& d) {
  Vec6 j;
  j << Vec3::Zero(), d;
  return j;
}

// Any unit vector perpendicular to n, chosen deterministically from n alone.
Vec3 perpendicular(const Vec3& n) {
  const Vec3 helper = std::abs(n.x()) < 0.57 ? Vec3::UnitX() : Vec3::UnitY();
  return n.cross(helper).normalized();
}

double row_velocity(const Rows& rows, int r, const Bodies& bodies) {
  double v = 0;
  for (int s = 0; s < 2; ++s) {
    const int k = rows.body[r][s];
    if (k < 0) continue;
    v += rows.jac[r][s].head<3>().dot(bodies.v[k]) + rows.jac[r][s].tail<3>().dot(bodies.w[k]);
  }
  return v;
}

Vec3 point_velocity(const std::vector<Vec3>& v, const std::vector<Vec3>& w, int k, const Vec3& r) {
  return v[k] + w[k].cross(r);
}

}  // namespace

// (J M^-1 J^T)_jj of a row, the scale of its regularisation floor.
double row_diagonal(const Rows& rows, int r, const Bodies& bodies) {
  double d = 0;
  for (int s = 0; s < 2; ++s) {
    const int k = rows.body[r][s];
    if (k < 0) continue;
    const Vec6& j = rows.jac[r][s];
    d += bodies.inv_mass[k] * j.head<3>().squaredNorm() + j.tail<3>().dot(bodies.inv_inertia[k] * j.tail<3>());
  }
  return d;
}

namespace {

// Sets row r as contact c's normal row.
void set_contact_normal_row(const Contact& c, const Bodies& bodies, int r, Rows& rows) {
  const int a = c.body_a;
  const int b = c.body_b >= 0 && !bodies.is_static[c.body_b] ? c.body_b : -1;
  rows.set(r, RowKind::Normal, a, b, contact_row_key(c.id, 0));
  rows.jac[r][0] = point_jacobian(c.normal, c.point - bodies.x[a]);
  if (b >= 0) rows.jac[r][1] = -point_jacobian(c.normal, c.point - bodies.x[b]);
}

}  // namespace

int add_contact_normal_row(const Contact& c, const Bodies& bodies, Rows& rows) {
  const int r = static_cast<int>(rows.size());
  rows.resize(rows.size() + 1);
  set_contact_normal_row(c, bodies, r, rows);
  return r;
}

std::vector<JointFrame> make_joint_frames(const SceneDef& scene, const Bodies& bodies) {
  std::vector<JointFrame> frames;
  frames.reserve(scene.joints.size());
  for (const JointDef& j : scene.joints) {
    JointFrame f;
    f.type = j.type;
    f.compliance = j.compliance;
    const int ids[2] = {j.body_a, j.body_b};
    Quat q[2] = {Quat::Identity(), Quat::Identity()};
    for (int s = 0; s < 2; ++s) {
      const int k = ids[s];
      if (k >= 0 && !bodies.is_static[k]) {
        f.body[s] = k;
        q[s] = bodies.q[k];
        f.anchor[s] = bodies.q[k].conjugate() * (j.anchor - bodies.x[k]);
        f.axis[s] = bodies.q[k].conjugate() * j.axis.normalized();
      } else {
        f.anchor[s] = j.anchor;  // a static body never moves: its anchor stays where it started
        f.axis[s] = j.axis.normalized();
      }
    }
    f.rest = q[0].conjugate() * q[1];
    frames.push_back(f);
  }
  return frames;
}

void WarmStart::store(const Rows& rows) {
  entries_.resize(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    Vec3 dir = Vec3::Zero();
    if (rows.kind[r] == RowKind::Friction) {
      const int k = rows.body[r][0] >= 0 ? 0 : 1;
      dir = (k == 0 ? 1.0 : -1.0) * rows.jac[r][k].head<3>();
    }
    entries_[r] = {rows.key[r], rows.lambda[r], rows.state[r], dir};
  }
  std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
}

const WarmStart::Entry* WarmStart::lookup(std::uint64_t key) const {
  auto it = std::lower_bound(entries_.begin(), entries_.end(), key,
                             [](const Entry& e, std::uint64_t k) { return e.key < k; });
  return it != entries_.end() && it->key == key ? &*it : nullptr;
}

bool WarmStart::find(std::uint64_t key, double& lambda, RowState& state) const {
  const Entry* e = lookup(key);
  if (!e) return false;
  lambda = e->lambda;
  state = e->state;
  return true;
}

void WarmStart::find_contact(std::uint64_t contact_id, const Entry* (&rows)[3]) const {
  const std::uint64_t first = contact_row_key(contact_id, 0);
  auto it = std::lower_bound(entries_.begin(), entries_.end(), first,
                             [](const Entry& e, std::uint64_t k) { return e.key < k; });
  for (int k = 0; k < 3; ++k) {
    const bool found = it != entries_.end() && it->key == first + static_cast<std::uint64_t>(k);
    rows[k] = found ? &*it : nullptr;
    if (found) ++it;
  }
}

void append_joint_rows(const std::vector<JointFrame>& joints, const Bodies& bodies, Rows& rows) {
  // 3 point rows per joint, plus 2 (hinge) or 3 (fixed) angular rows.
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const JointFrame& f = joints[j];
    const int a = f.body[0], b = f.body[1];
    if (a < 0 && b < 0) continue;  // nothing dynamic to hold
    Vec3 r[2], p[2];
    Quat q[2];
    for (int s = 0; s < 2; ++s) {
      const int k = f.body[s];
      q[s] = k >= 0 ? bodies.q[k] : Quat::Identity();
      r[s] = k >= 0 ? Vec3(bodies.q[k] * f.anchor[s]) : Vec3::Zero();
      p[s] = k >= 0 ? Vec3(bodies.x[k] + r[s]) : f.anchor[s];
    }
    const Vec3 drift = p[0] - p[1];
    int k = 0;
    auto add_row = [&](const Vec6& ja, const Vec6& jb, double error) {
      const int row = rows.add(RowKind::Joint, a, b, joint_row_key(static_cast<int>(j), k++));
      rows.jac[row][0] = ja;
      rows.jac[row][1] = jb;
      rows.q[row] = error;
      rows.sigma[row] = f.compliance;
    };
    for (int d = 0; d < 3; ++d) {
      const Vec3 e = Vec3::Unit(d);
      add_row(a >= 0 ? point_jacobian(e, r[0]) : Vec6::Zero(), b >= 0 ? Vec6(-point_jacobian(e, r[1])) : Vec6::Zero(),
              drift[d]);
    }
    if (f.type == JointType::Hinge) {
      // Two rows stop relative rotation about axes perpendicular to the hinge axis; the error
      // a_b x a_a measures the axes' misalignment (small-angle, docs/design.md#dynamics).
      const Vec3 axis_a = a >= 0 ? Vec3(q[0] * f.axis[0]) : f.axis[0];
      const Vec3 axis_b = b >= 0 ? Vec3(q[1] * f.axis[1]) : f.axis[1];
      const Vec3 t1 = perpendicular(axis_a);
      const Vec3 t2 = axis_a.cross(t1);
      const Vec3 error = axis_b.cross(axis_a);
      for (const Vec3& t : {t1, t2})
        add_row(a >= 0 ? angular_jacobian(t) : Vec6::Zero(), b >= 0 ? Vec6(-angular_jacobian(t)) : Vec6::Zero(),
                t.dot(error));
    } else if (f.type == JointType::Fixed) {
      // Rotation error of a relative to where b says it should be: q_a rest q_b^-1 = [1, theta/2].
      Quat qe = q[0] * f.rest * q[1].conjugate();
      if (qe.w() < 0) qe.coeffs() = -qe.coeffs();
      const Vec3 theta = 2.0 * qe.vec();
      for (int d = 0; d < 3; ++d) {
        const Vec3 e = Vec3::Unit(d);
        add_row(a >= 0 ? angular_jacobian(e) : Vec6::Zero(), b >= 0 ? Vec6(-angular_jacobian(e)) : Vec6::Zero(),
                theta[d]);
      }
    }
  }
}

void assemble_rows(const std::vector<Contact>& contacts, const std::vector<JointFrame>& joints,
                   const Bodies& bodies, const std::vector<Vec3>& sliding_v,
                   const std::vector<Vec3>& sliding_w, const StepParams& params, double h,
                   const WarmStart& warm, Rows& rows) {
  const double inv_h = 1.0 / h;

  // Contacts: one normal row and two friction rows each, rows 3i to 3i + 2 for contact i, in
  // parallel (each contact writes only its own rows, every field of them: the last step's values
  // in place are not read).
  rows.resize(3 * contacts.size());
  parallel_for_chunked(contacts.size(), kGrain, [&](std::size_t i) {
    const Contact& c = contacts[i];
    const int a = c.body_a;
    const int b = c.body_b >= 0 && !bodies.is_static[c.body_b] ? c.body_b : -1;
    const Vec3 ra = c.point - bodies.x[a];
    const Vec3 rb = b >= 0 ? Vec3(c.point - bodies.x[b]) : Vec3::Zero();

    const int n_row = static_cast<int>(3 * i);
    set_contact_normal_row(c, bodies, n_row, rows);
    // Penetration beyond the slop is pushed out at rate erp/h; a gap may close within the step
    // (speculative contact) but is never pulled shut.
    const double bias = c.distance < 0 ? params.erp * inv_h * std::min(0.0, c.distance + params.slop)
                                       : c.distance * inv_h;

    // Tangent t1 along the sliding velocity so a sliding contact feels exactly mu * lambda_n.
    Vec3 vrel = point_velocity(sliding_v, sliding_w, a, ra);
    if (b >= 0) vrel -= point_velocity(sliding_v, sliding_w, b, rb);
    const Vec3 vt = vrel - c.normal * c.normal.dot(vrel);
    const double speed = vt.norm();
    const Vec3 t1 = speed > params.sliding_velocity_eps ? Vec3(vt / speed) : perpendicular(c.normal);
    const Vec3 t2 = c.normal.cross(t1);
    const double mu = std::sqrt(bodies.friction[a] * bodies.friction[c.body_b]);
    // The last step's impulses and states; friction's as the world-frame impulse it applied,
    // projected on the new tangents.
    const WarmStart::Entry* last[3];
    warm.find_contact(c.id, last);
    Vec3 f_warm = Vec3::Zero();
    for (int k = 1; k <= 2; ++k)
      if (last[k]) f_warm += last[k]->lambda * last[k]->direction;
    const Vec3 tangents[2] = {t1, t2};
    for (int k = 0; k < 2; ++k) {
      const int r = n_row + 1 + k;
      rows.set(r, RowKind::Friction, a, b, contact_row_key(c.id, k + 1));
      rows.jac[r][0] = point_jacobian(tangents[k], ra);
      if (b >= 0) rows.jac[r][1] = -point_jacobian(tangents[k], rb);
      rows.normal_of[r] = n_row;
      rows.mu[r] = mu;
      if (last[k + 1]) rows.state[r] = last[k + 1]->state;
      rows.lambda[r] = f_warm.dot(tangents[k]);
    }
    rows.q[n_row] = bias;
    if (last[0]) {
      rows.lambda[n_row] = last[0]->lambda;
      rows.state[n_row] = last[0]->state;
    }
    // The friction of a contact of the step before yields while its impulses change: w_t +=
    // contact_prox D_t (lambda_t - warm_t), D_t the row's diagonal of J M^-1 J^T. At rest (the
    // impulses repeat) it is rigid and does not creep, as it would under a plain sigma of that size;
    // but a Newton piece that is wrong on a contact's redundant friction rows (eight on a resting
    // face's three planar freedoms) swings their impulses by ~ w / (contact_prox D_t), not by
    // ~ w / (sigma_floor D_t). A new contact (an impact, a cold start) is rigid, and so are normals:
    // the term on them lets a light body under a heavy one yield by centimetres while its load
    // changes (bench/results/intel-xeon-2core/contact-prox/).
    if (last[0])
      for (int r = n_row + 1; r < n_row + 3; ++r) {
        const double yield = params.contact_prox * row_diagonal(rows, r, bodies);
        rows.sigma[r] += yield;
        rows.q[r] -= yield * rows.lambda[r];
      }
  });

  // Joints: position errors become Baumgarte rates, compliances regularisations.
  const std::size_t first_joint_row = rows.size();
  append_joint_rows(joints, bodies, rows);
  for (std::size_t r = first_joint_row; r < rows.size(); ++r) {
    rows.q[r] *= params.erp * inv_h;
    rows.sigma[r] *= inv_h * inv_h;
  }

  // Rigid-row floor on sigma, q = J u* + b, warm starts of joint rows (each row its own).
  parallel_for_chunked(rows.size(), kGrain, [&](std::size_t r) {
    const int row = static_cast<int>(r);
    rows.sigma[r] += params.sigma_floor * row_diagonal(rows, row, bodies);
    rows.q[r] += row_velocity(rows, row, bodies);
    if (rows.kind[r] == RowKind::Joint) {
      double lambda;
      RowState state;
      if (warm.find(rows.key[r], lambda, state)) {
        rows.lambda[r] = lambda;
        rows.state[r] = state;
      }
    }
  });
}

}  // namespace rbpart
