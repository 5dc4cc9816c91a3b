// The integration stage (integrate/integrate.hpp) against mechanics: free flight follows the
// semi-implicit Euler recurrence exactly (and so the parabola to O(h)), a spin about a principal
// axis turns by the discrete angle 2 atan(h w / 2) per step, a torque-free tumble keeps its angular
// momentum to first order in h, impulses change the velocities by a dense M^-1 J^T lambda and
// conserve momentum when they act in equal and opposite pairs, and the world inertia is the
// rotated body inertia plus the joints' geometric stiffness.
#include "integrate/integrate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "assembly/assemble.hpp"
#include "support/bodies.hpp"

namespace rbpart {
namespace {

using test::add_box;
using test::add_static;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kStep = 1.0 / 60.0;
const Vec3 kGravity(0, 0, -9.81);

// One step of free motion, as the step runs it without contacts: inertia, u* = u + h M^-1 f_ext,
// then the positions.
void free_step(Bodies& b, const Vec3& gravity, double h) {
  update_world_inertia(b);
  apply_external_forces(b, gravity, h);
  integrate_positions(b, h);
}

Vec3 angular_momentum(const Bodies& b) {
  Vec3 l = Vec3::Zero();
  for (int k = 0; k < b.size(); ++k) {
    if (b.is_static[k]) continue;
    const Mat3 R = b.q[k].toRotationMatrix();
    l += b.x[k].cross(b.mass[k] * b.v[k]) + R * b.inertia_body[k] * R.transpose() * b.w[k];
  }
  return l;
}

Vec3 linear_momentum(const Bodies& b) {
  Vec3 p = Vec3::Zero();
  for (int k = 0; k < b.size(); ++k) p += b.mass[k] * b.v[k];
  return p;
}

TEST(Integrate, FreeFlightFollowsTheSemiImplicitEulerRecurrence) {
  // v_n = v_0 + n h g and x_n = x_{n-1} + h v_n, so x_n = x_0 + n h v_0 + n (n + 1)/2 h^2 g: the
  // parabola x(t_n) = x_0 + v_0 t_n + g t_n^2 / 2 plus h t_n g / 2. A static body stays put.
  Bodies b;
  add_static(b, Vec3(0, 0, -1));
  const Vec3 x0(0.2, 0.1, 1.0), v0(1.0, -0.5, 3.0);
  add_box(b, 2.0, Vec3(0.3, 0.2, 0.1), x0, Quat(Eigen::AngleAxisd(0.5, Vec3::UnitY())));
  b.v[1] = v0;
  const Quat q0 = b.q[1];
  const int n = 120;
  for (int i = 0; i < n; ++i) free_step(b, kGravity, kStep);
  const double t = n * kStep;
  const Vec3 recurrence = x0 + n * kStep * v0 + 0.5 * n * (n + 1) * kStep * kStep * kGravity;
  const Vec3 parabola = x0 + v0 * t + 0.5 * kGravity * t * t;
  // Round-off: n additions to a position of size |x|, each good to a few eps.
  const double scale = x0.norm() + t * v0.norm() + t * t * kGravity.norm();
  EXPECT_LE((b.v[1] - (v0 + t * kGravity)).norm(), 4 * n * kEps * (v0.norm() + t * kGravity.norm()));
  EXPECT_LE((b.x[1] - recurrence).norm(), 4 * n * kEps * scale);
  EXPECT_LE((b.x[1] - parabola - 0.5 * kStep * t * kGravity).norm(), 4 * n * kEps * scale);
  EXPECT_EQ(b.w[1], Vec3::Zero());
  EXPECT_LE(b.q[1].angularDistance(q0), 4 * n * kEps);  // normalised each step, turned never
  EXPECT_EQ(b.x[0], Vec3(0, 0, -1));
  EXPECT_EQ(b.v[0], Vec3::Zero());
}

TEST(Integrate, SpinAboutAPrincipalAxisTurnsByTheDiscreteAngle) {
  // About a principal axis w x I w = 0: w stays, and each step q <- (1, h w / 2) q / |.| turns the
  // body by 2 atan(h |w| / 2) about w (|w| h - (|w| h)^3 / 12 + ...: slightly less than |w| h).
  // The quaternion stays unit.
  Bodies b;
  const Quat q0(Eigen::AngleAxisd(0.8, Vec3(1, -2, 1).normalized()));
  add_box(b, 2.0, Vec3(0.3, 0.2, 0.1), Vec3::Zero(), q0);
  const double spin = 12.0;
  const Vec3 w = q0 * Vec3(0, 0, spin);
  b.w[0] = w;
  const int n = 120;
  for (int i = 0; i < n; ++i) {
    free_step(b, Vec3::Zero(), kStep);
    ASSERT_NEAR(b.q[0].norm(), 1, 4 * kEps);
  }
  EXPECT_LE((b.w[0] - w).norm(), 64 * n * kEps * spin);
  const double step_angle = 2 * std::atan(kStep * spin / 2);
  const Quat expected = Quat(Eigen::AngleAxisd(n * step_angle, w.normalized())) * q0;
  EXPECT_LE(b.q[0].angularDistance(expected), 64 * n * kEps);
  // The continuous turn differs by n (h w)^3 / 12 to leading order: the test can tell them apart.
  const Quat exact = Quat(Eigen::AngleAxisd(n * kStep * spin, w.normalized())) * q0;
  EXPECT_NEAR(b.q[0].angularDistance(exact), n * std::pow(kStep * spin, 3) / 12, 0.01 * n * std::pow(kStep * spin, 3));
}

// Relative change of the world angular momentum of a box tumbling torque-free for 1 s at step h.
double tumble_drift(double h, double* energy_ratio = nullptr) {
  Bodies b;
  add_box(b, 2.0, Vec3(0.3, 0.2, 0.1), Vec3::Zero(), Quat(Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized())));
  b.w[0] = b.q[0] * Vec3(1.0, 0.5, 4.0);  // mostly about the major axis z, tumbling
  const Vec3 l0 = angular_momentum(b);
  const auto energy = [&] {
    const Mat3 R = b.q[0].toRotationMatrix();
    return 0.5 * b.w[0].dot(R * b.inertia_body[0] * R.transpose() * b.w[0]);
  };
  const double e0 = energy();
  const int n = static_cast<int>(std::lround(1.0 / h));
  for (int i = 0; i < n; ++i) free_step(b, Vec3::Zero(), h);
  if (energy_ratio) *energy_ratio = energy() / e0;
  return (angular_momentum(b) - l0).norm() / l0.norm();
}

TEST(Integrate, TorqueFreeTumbleKeepsItsAngularMomentumToFirstOrder) {
  // The gyroscopic step (backward Euler, one Newton step, in the body frame) and the rotation are
  // each first-order accurate, so the world angular momentum drifts as C h: halving h halves the
  // drift, the ratio 2 + O(|w| h) (|w| h ~ 0.02 here). The implicit step loses energy rather than
  // gaining it (Catto 2015), also at first order.
  double e1, e2;
  const double d1 = tumble_drift(1.0 / 240, &e1), d2 = tumble_drift(1.0 / 480, &e2);
  EXPECT_GT(d1, 0);
  EXPECT_NEAR(d1 / d2, 2.0, 0.1);
  EXPECT_LT(e1, 1.0);
  EXPECT_LT(e2, 1.0);
  EXPECT_NEAR((1 - e1) / (1 - e2), 2.0, 0.1);
}

TEST(Integrate, ImpulsesChangeVelocitiesByInverseMassTimesJTransposeLambda) {
  // u+ = u* + M^-1 J^T lambda, against a dense M^-1 (from the rotated body inertias) and a dense J
  // of random rows over three turned boxes (a row's second body may be none).
  Bodies b;
  add_static(b, Vec3(0, 0, -1));
  add_box(b, 2.0, Vec3(0.3, 0.2, 0.1), Vec3(0, 0, 0.5), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())));
  add_box(b, 0.5, Vec3(0.1, 0.1, 0.4), Vec3(1, 0, 0.5), Quat(Eigen::AngleAxisd(-1.1, Vec3(-2, 1, 1).normalized())));
  add_box(b, 9.0, Vec3(0.5, 0.2, 0.2), Vec3(0, 1, 0.5), Quat(Eigen::AngleAxisd(2.0, Vec3(0, 1, 1).normalized())));
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> body(1, 3);
  Rows rows;
  const int m = 10;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m, 6 * b.size());
  Eigen::VectorXd lambda(m);
  for (int r = 0; r < m; ++r) {
    const int a = body(rng), c = r % 3 == 0 ? -1 : 1 + (a + body(rng) - 1) % 3;
    rows.add(RowKind::Joint, a, c == a ? -1 : c, r);
    for (int s = 0; s < 2; ++s) {
      if (rows.body[r][s] < 0) continue;
      for (int i = 0; i < 6; ++i) rows.jac[r][s][i] = u(rng);
      J.block<1, 6>(r, 6 * rows.body[r][s]) += rows.jac[r][s].transpose();
    }
    rows.lambda[r] = lambda[r] = u(rng);
  }
  Eigen::VectorXd before(6 * b.size());
  for (int k = 0; k < b.size(); ++k) {
    if (!b.is_static[k]) b.v[k] = Vec3(u(rng), u(rng), u(rng)), b.w[k] = Vec3(u(rng), u(rng), u(rng));
    before.segment<6>(6 * k) << b.v[k], b.w[k];
  }
  const Eigen::MatrixXd inverse_mass = test::inverse_mass_matrix(b);
  const Eigen::VectorXd expected = before + inverse_mass * J.transpose() * lambda;
  // Round-off: sums of at most m + 6 products, each good to a few eps of |M^-1| |J|^T |lambda|.
  const Eigen::VectorXd bound =
      before.cwiseAbs() + inverse_mass.cwiseAbs() * J.cwiseAbs().transpose() * lambda.cwiseAbs();
  apply_impulses(rows, b);
  for (int k = 0; k < b.size(); ++k)
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(b.v[k][i], expected[6 * k + i], 8 * (m + 6) * kEps * bound[6 * k + i]) << "body " << k;
      EXPECT_NEAR(b.w[k][i], expected[6 * k + 3 + i], 8 * (m + 6) * kEps * bound[6 * k + 3 + i]) << "body " << k;
    }
  EXPECT_EQ(b.v[0], Vec3::Zero());
  EXPECT_EQ(b.w[0], Vec3::Zero());
}

TEST(Integrate, ContactImpulsesConserveMomentum) {
  // A contact row applies lambda n to body a and -lambda n to body b at the same point: Newton's
  // third law, so the pair's linear momentum and its angular momentum about any point are unchanged.
  Bodies b;
  add_box(b, 2.0, Vec3(0.3, 0.2, 0.1), Vec3(0, 0, 0.5), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())));
  add_box(b, 0.5, Vec3(0.1, 0.1, 0.4), Vec3(0.3, 0.2, 0.9), Quat(Eigen::AngleAxisd(-1.1, Vec3(-2, 1, 1).normalized())));
  b.v = {Vec3(1, 0, -1), Vec3(0, 0.5, 0)};
  b.w = {Vec3(0, 2, 0), Vec3(-1, 0, 3)};
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  Rows rows;
  for (int i = 0; i < 4; ++i) {
    Contact c;
    c.body_a = 1;
    c.body_b = 0;
    c.point = Vec3(0.15, 0.1, 0.7) + 0.1 * Vec3(u(rng), u(rng), u(rng));
    c.normal = Vec3(u(rng), u(rng), 1).normalized();
    c.id = i;
    const int r = add_contact_normal_row(c, b, rows);
    rows.lambda[r] = 2 + u(rng);
  }
  const Vec3 p0 = linear_momentum(b), l0 = angular_momentum(b);
  apply_impulses(rows, b);
  const Vec3 p1 = linear_momentum(b), l1 = angular_momentum(b);
  EXPECT_GT((b.v[0] - Vec3(1, 0, -1)).norm(), 0.5);  // the impulses were felt
  // Round-off: a few eps of the momenta and of the impulses (about 12 N s, at levers below 1 m).
  EXPECT_LE((p1 - p0).norm(), 64 * kEps * (p0.norm() + 12));
  EXPECT_LE((l1 - l0).norm(), 64 * kEps * (l0.norm() + 12));
}

TEST(Integrate, WorldInertiaIsTheRotatedBodyInertiaPlusStiffness) {
  // The body's principal axes R e_i are eigenvectors of the world inverse inertia with eigenvalues
  // 1 / (I_i + k), k the geometric stiffness; a static body's is zero.
  Bodies b;
  add_static(b, Vec3(0, 0, -1));
  const Quat q(Eigen::AngleAxisd(1.3, Vec3(2, -1, 1).normalized()));
  add_box(b, 2.0, Vec3(0.3, 0.2, 0.1), Vec3::Zero(), q);
  add_box(b, 2.0, Vec3(0.3, 0.2, 0.1), Vec3::Zero(), q);
  b.geometric_stiffness[2] = 0.05;
  b.inv_inertia[0] = Mat3::Identity();  // stale values, to be replaced
  update_world_inertia(b);
  EXPECT_TRUE(b.inv_inertia[0].isZero());
  const Mat3 R = q.toRotationMatrix();
  for (int k : {1, 2})
    for (int i = 0; i < 3; ++i) {
      const double eigenvalue = 1 / (b.inertia_body[k](i, i) + b.geometric_stiffness[k]);
      EXPECT_LE((b.inv_inertia[k] * R.col(i) - eigenvalue * R.col(i)).norm(), 64 * kEps * eigenvalue)
          << "body " << k << " axis " << i;
    }
}

TEST(Integrate, GeometricStiffnessIsTheJointLoadTimesItsLever) {
  // A ball joint carrying the force f over a step (lambda = h f) at lever r from body a's centre:
  // k = h sum_d |lambda_d| |r x e_d|, which is h^2 |f| |r| for f perpendicular to r (Andrews et al.
  // 2017, diagonal). Contact rows carry no stiffness; the last step's values are replaced.
  Bodies b;
  add_box(b, 2.0, Vec3(0.1, 0.1, 0.5), Vec3(0, 0, 0));
  add_box(b, 2.0, Vec3(0.1, 0.1, 0.5), Vec3(0, 0, 1));
  const Vec3 f(-30, 0, 0);
  const double lever = 0.5;
  JointDef def;
  def.body_a = 0;
  def.body_b = 1;
  def.anchor = Vec3(0, 0, lever);
  SceneDef scene;
  scene.joints = {def};
  Rows rows;
  append_joint_rows(make_joint_frames(scene, b), b, rows);
  for (int d = 0; d < 3; ++d) rows.lambda[d] = kStep * f[d];
  Contact c;
  c.body_a = 0;
  c.body_b = 1;
  c.point = Vec3(0.1, 0, 0.5);
  c.normal = Vec3::UnitZ();
  rows.lambda[add_contact_normal_row(c, b, rows)] = 1e3;
  b.geometric_stiffness = {7, 7};
  update_geometric_stiffness(rows, b, kStep);
  for (int k : {0, 1}) EXPECT_NEAR(b.geometric_stiffness[k], kStep * kStep * f.norm() * lever, 8 * kEps * kStep * kStep * f.norm() * lever);
}

}  // namespace
}  // namespace rbpart
