// The assembly stage (assembly/assemble.hpp) against the mechanics of docs/design.md#dynamics: a
// contact row's J u is the relative velocity of the two bodies' material points along its
// direction, friction directions are orthonormal and tangent, q - J u* is the Baumgarte or
// speculative term, sigma the compliance over h^2 plus the floor times (J M^-1 J^T)_jj from a dense
// mass matrix, mu the geometric mean; joint rows measure the relative anchor velocity and angular
// velocity and their b the drift; warm starts carry impulses by id and keep the world friction
// impulse.
#include "assembly/assemble.hpp"

#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "support/bodies.hpp"

namespace rbpart {
namespace {

using test::add_box;
using test::add_static;
using test::point_velocity;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kStep = 1.0 / 60.0;

int row_with_key(const Rows& rows, std::uint64_t key) {
  for (std::size_t r = 0; r < rows.size(); ++r)
    if (rows.key[r] == key) return static_cast<int>(r);
  ADD_FAILURE() << "no row with key " << key;
  return 0;
}

// J_r u for the velocities in `b`, and the sum of |terms|, the scale of its round-off.
double row_times(const Rows& rows, int r, const Bodies& b, double* scale = nullptr) {
  double v = 0, s = 0;
  for (int k = 0; k < 2; ++k) {
    const int body = rows.body[r][k];
    if (body < 0) continue;
    Vec6 u;
    u << b.v[body], b.w[body];
    v += rows.jac[r][k].dot(u);
    s += rows.jac[r][k].cwiseAbs().dot(u.cwiseAbs());
  }
  if (scale) *scale = s;
  return v;
}

// The dense row J_r over every body's 6 velocities.
Eigen::RowVectorXd dense_row(const Rows& rows, int r, int bodies) {
  Eigen::RowVectorXd j = Eigen::RowVectorXd::Zero(6 * bodies);
  for (int k = 0; k < 2; ++k)
    if (rows.body[r][k] >= 0) j.segment<6>(6 * rows.body[r][k]) = rows.jac[r][k].transpose();
  return j;
}

void randomise_velocities(Bodies& b, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-2, 2);
  for (int k = 0; k < b.size(); ++k)
    if (!b.is_static[k]) b.v[k] = Vec3(u(rng), u(rng), u(rng)), b.w[k] = Vec3(u(rng), u(rng), u(rng));
}

void assemble(const std::vector<Contact>& contacts, const std::vector<JointFrame>& joints, const Bodies& b,
              const StepParams& params, Rows& rows, const WarmStart& warm = WarmStart{}) {
  assemble_rows(contacts, joints, b, b.v, b.w, params, kStep, warm, rows);
}

Contact contact(int a, int b, const Vec3& point, const Vec3& normal, double distance, std::uint64_t id) {
  Contact c;
  c.body_a = a;
  c.body_b = b;
  c.point = point;
  c.normal = normal.normalized();
  c.distance = distance;
  c.id = id;
  return c;
}

// Body 0 static ground, 1 and 2 boxes turned every way, one contact between them (id 3) and one of
// box 1 on the ground (id 8).
struct TwoBoxes {
  Bodies bodies;
  std::vector<Contact> contacts;
  TwoBoxes() {
    add_static(bodies, Vec3(0, 0, -1), 0.8);
    add_box(bodies, 2.0, Vec3(0.3, 0.2, 0.1), Vec3(0.1, 0.2, 0.3), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())), 0.5);
    add_box(bodies, 7.0, Vec3(0.2, 0.2, 0.4), Vec3(0.4, -0.1, 0.9), Quat(Eigen::AngleAxisd(-1.1, Vec3(-2, 1, 1).normalized())), 0.2);
    contacts.push_back(contact(2, 1, Vec3(0.3, 0.05, 0.55), Vec3(0.2, -0.3, 1), -0.001, 3));
    contacts.push_back(contact(1, 0, Vec3(0.05, 0.3, 0.02), Vec3(0, 0, 1), 0, 8));
  }
};

TEST(Assemble, ContactRowsMeasureTheRelativeVelocityOfTheTouchingPoints) {
  // J u = d . (v_a + w_a x r_a - v_b - w_b x r_b) for the normal n and two tangents t1, t2 that
  // with n form an orthonormal frame; a static b owns no unknowns.
  TwoBoxes s;
  std::mt19937 rng(1);
  Rows rows;
  for (int trial = 0; trial < 4; ++trial) {
    randomise_velocities(s.bodies, rng);
    assemble(s.contacts, {}, s.bodies, StepParams{}, rows);
    ASSERT_EQ(rows.size(), 6u);
    for (const Contact& c : s.contacts) {
      SCOPED_TRACE(c.id);
      const int b = s.bodies.is_static[c.body_b] ? -1 : c.body_b;
      const Vec3 relative = point_velocity(s.bodies, c.body_a, c.point) -
                            (b >= 0 ? point_velocity(s.bodies, b, c.point) : Vec3::Zero());
      const int n = row_with_key(rows, contact_row_key(c.id, 0));
      Vec3 t[2];
      for (int k = 0; k < 3; ++k) {
        const int r = row_with_key(rows, contact_row_key(c.id, k));
        EXPECT_EQ(rows.body[r][0], c.body_a);
        EXPECT_EQ(rows.body[r][1], b);
        if (b < 0) EXPECT_TRUE(rows.jac[r][1].isZero());
        const Vec3 d = rows.jac[r][0].head<3>();
        if (k > 0) t[k - 1] = d;
        double scale;
        const double ju = row_times(rows, r, s.bodies, &scale);
        EXPECT_NEAR(ju, d.dot(relative), 16 * kEps * scale) << "row kind " << k;
        EXPECT_EQ(rows.kind[r], k == 0 ? RowKind::Normal : RowKind::Friction);
        EXPECT_EQ(rows.normal_of[r], k == 0 ? -1 : n);
      }
      EXPECT_EQ(Vec3(rows.jac[n][0].head<3>()), c.normal);
      for (int k = 0; k < 2; ++k) {
        EXPECT_NEAR(t[k].norm(), 1, 4 * kEps);
        EXPECT_NEAR(t[k].dot(c.normal), 0, 4 * kEps);
      }
      EXPECT_NEAR(t[0].dot(t[1]), 0, 4 * kEps);
      // The normal row's bounds are [0, inf); a friction row's are set by the solver from it.
      EXPECT_EQ(rows.lo[n], 0.0);
      EXPECT_EQ(rows.hi[n], kInf);
    }
  }
}

TEST(Assemble, NormalRowBiasIsBaumgarteInPenetrationAndTheGapWhenApart) {
  // b = (erp/h) min(0, d + slop) for d < 0: penetration beyond the slop is pushed out at rate erp/h,
  // within it left alone; b = d/h for d >= 0: a gap may close within the step, no further.
  // Friction rows have b = 0.
  StepParams params;
  params.erp = 0.3;
  params.slop = 0.001;
  for (double d : {-0.02, -0.0015, -0.0005, 0.0, 0.004}) {
    SCOPED_TRACE(d);
    TwoBoxes s;
    std::mt19937 rng(2);
    randomise_velocities(s.bodies, rng);
    s.contacts[1].distance = d;
    Rows rows;
    assemble(s.contacts, {}, s.bodies, params, rows);
    const double b = d < -params.slop ? params.erp / kStep * (d + params.slop) : d < 0 ? 0.0 : d / kStep;
    for (int k = 0; k < 3; ++k) {
      const int r = row_with_key(rows, contact_row_key(8, k));
      double scale;
      const double ju = row_times(rows, r, s.bodies, &scale);
      EXPECT_NEAR(rows.q[r] - ju, k == 0 ? b : 0.0, 16 * kEps * (scale + std::abs(b))) << "row kind " << k;
    }
  }
}

TEST(Assemble, SigmaIsComplianceOverHSquaredPlusTheFloorOfTheRowsEffectiveMass) {
  // sigma_j = c / h^2 + sigma_floor (J M^-1 J^T)_jj, with M^-1 built densely from the masses and the
  // rotated body inertias; contacts are rigid (c = 0).
  TwoBoxes s;
  JointDef def;
  def.type = JointType::Fixed;
  def.body_a = 1;
  def.body_b = 2;
  def.anchor = Vec3(0.3, 0.1, 0.6);
  def.compliance = 1e-4;
  SceneDef scene;
  scene.joints = {def};
  StepParams params;
  params.sigma_floor = 1e-3;
  Rows rows;
  assemble(s.contacts, make_joint_frames(scene, s.bodies), s.bodies, params, rows);
  ASSERT_EQ(rows.size(), 12u);
  const Eigen::MatrixXd inverse_mass = test::inverse_mass_matrix(s.bodies);
  for (int r = 0; r < static_cast<int>(rows.size()); ++r) {
    const Eigen::RowVectorXd j = dense_row(rows, r, s.bodies.size());
    const double diagonal = j * inverse_mass * j.transpose();
    EXPECT_NEAR(row_diagonal(rows, r, s.bodies), diagonal, 64 * kEps * diagonal) << "row " << r;
    const double compliance = rows.kind[r] == RowKind::Joint ? def.compliance / (kStep * kStep) : 0.0;
    EXPECT_NEAR(rows.sigma[r], compliance + params.sigma_floor * diagonal, 64 * kEps * rows.sigma[r]) << "row " << r;
    EXPECT_GT(rows.sigma[r], 0);
  }
}

TEST(Assemble, FrictionCoefficientIsTheGeometricMeanOfTheBodies) {
  // mu = sqrt(mu_a mu_b) (docs/formats.md): 0.8 and 0.5 give sqrt(0.4), 0.5 and 0.2 give 0.1^(1/2).
  TwoBoxes s;
  Rows rows;
  assemble(s.contacts, {}, s.bodies, StepParams{}, rows);
  const std::pair<std::uint64_t, double> expected[] = {{3, std::sqrt(0.5 * 0.2)}, {8, std::sqrt(0.5 * 0.8)}};
  for (const auto& [id, mu] : expected) {
    EXPECT_EQ(rows.mu[row_with_key(rows, contact_row_key(id, 0))], 0.0);
    for (int k = 1; k <= 2; ++k) EXPECT_NEAR(rows.mu[row_with_key(rows, contact_row_key(id, k))], mu, 2 * kEps * mu);
  }
}

TEST(Assemble, FirstTangentFollowsTheSlidingVelocity) {
  // A box sliding and spinning on the ground: the velocity before external forces (not u*) defines
  // t1, so that J_t1 u_slide = |v_t| and J_t2 u_slide = 0 at the contact point: a sliding contact
  // feels exactly mu lambda_n against its motion.
  Bodies b;
  add_static(b, Vec3(0, 0, -1));
  add_box(b, 3.0, Vec3(0.5, 0.5, 0.5), Vec3(0, 0, 0.5));
  const std::vector<Vec3> sliding_v = {Vec3::Zero(), Vec3(0.3, -0.2, 0.0)};
  const std::vector<Vec3> sliding_w = {Vec3::Zero(), Vec3(0.1, 0.4, 1.5)};
  b.v[1] = sliding_v[1] + kStep * Vec3(0, 0, -9.81);  // u*: gravity added
  b.w[1] = sliding_w[1];
  const Contact c = contact(1, 0, Vec3(0.5, -0.5, 0), Vec3::UnitZ(), 0, 4);
  Rows rows;
  assemble_rows({c}, {}, b, sliding_v, sliding_w, StepParams{}, kStep, WarmStart{}, rows);
  const Vec3 slide = sliding_v[1] + sliding_w[1].cross(c.point - b.x[1]);
  const Vec3 tangential = slide - slide.dot(c.normal) * c.normal;
  const Vec3 t1 = rows.jac[row_with_key(rows, contact_row_key(4, 1))][0].head<3>();
  const Vec3 t2 = rows.jac[row_with_key(rows, contact_row_key(4, 2))][0].head<3>();
  EXPECT_NEAR(t1.dot(tangential), tangential.norm(), 8 * kEps * slide.norm());
  EXPECT_NEAR(t2.dot(tangential), 0, 8 * kEps * slide.norm());

  // Below sliding_velocity_eps the tangents depend on the normal alone.
  StepParams params;
  const std::vector<Vec3> creeping_v = {Vec3::Zero(), Vec3(0.3, 0.1, 0) * params.sliding_velocity_eps};
  const std::vector<Vec3> still_v = {Vec3::Zero(), Vec3::Zero()};
  const std::vector<Vec3> still_w = still_v;
  Rows creeping, still;
  assemble_rows({c}, {}, b, creeping_v, still_w, params, kStep, WarmStart{}, creeping);
  assemble_rows({c}, {}, b, still_v, still_w, params, kStep, WarmStart{}, still);
  for (int r = 0; r < 3; ++r) EXPECT_EQ(creeping.jac[r][0], still.jac[r][0]) << "row " << r;
}

TEST(Assemble, WarmStartCarriesImpulsesByIdAndKeepsTheWorldFrictionImpulse) {
  // Step 1: contacts 5 and 9 of a box on the ground and a ball joint to the world, solved with
  // some impulses. Step 2: the contacts come in another order with a new one (id 11), the box now
  // slides another way, so the tangents turn. The normal and joint impulses and all index sets
  // follow their keys; the friction impulse is re-expressed in the new tangents, f' = sum_k
  // (f . t'_k) t'_k: the same world impulse where the normal is unchanged, its projection onto the
  // new tangent plane where the normal turned. The new contact starts cold.
  Bodies b;
  add_static(b, Vec3(0, 0, -1));
  add_box(b, 3.0, Vec3(0.5, 0.5, 0.5), Vec3(0, 0, 0.5));
  b.v[1] = Vec3(1, 0, 0);
  JointDef def;
  def.body_a = 1;
  def.anchor = Vec3(0.5, 0.5, 1);
  SceneDef scene;
  scene.joints = {def};
  const std::vector<JointFrame> joints = make_joint_frames(scene, b);
  std::vector<Contact> contacts = {contact(1, 0, Vec3(0.5, 0.5, 0), Vec3::UnitZ(), 0, 5),
                                   contact(1, 0, Vec3(-0.5, 0.5, 0), Vec3::UnitZ(), 0, 9)};
  Rows rows;
  assemble(contacts, joints, b, StepParams{}, rows);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  const RowState states[] = {RowState::Free, RowState::Lower, RowState::Upper};
  for (std::size_t r = 0; r < rows.size(); ++r) {
    rows.lambda[r] = u(rng);
    rows.state[r] = states[r % 3];
  }
  const Rows solved = rows;
  auto friction = [](const Rows& x, std::uint64_t id) {
    Vec3 f = Vec3::Zero();
    for (int k = 1; k <= 2; ++k) {
      const int r = row_with_key(x, contact_row_key(id, k));
      f += x.lambda[r] * x.jac[r][0].head<3>();
    }
    return f;
  };
  WarmStart warm;
  warm.store(solved);

  const Vec3 tilted = Vec3(0.3, 0, 1).normalized();
  contacts = {contact(1, 0, Vec3(0, 0, 0), Vec3::UnitZ(), 0, 11), contact(1, 0, Vec3(-0.5, 0.5, 0), tilted, 0, 9),
              contact(1, 0, Vec3(0.5, 0.5, 0), Vec3::UnitZ(), 0, 5)};
  b.v[1] = Vec3(0.2, 0.7, 0);
  assemble(contacts, joints, b, StepParams{}, rows, warm);
  ASSERT_EQ(rows.size(), 12u);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    SCOPED_TRACE(rows.key[r]);
    const bool fresh = rows.key[r] / 4 == 11 && rows.kind[r] != RowKind::Joint;
    if (fresh) {
      EXPECT_EQ(rows.lambda[r], 0.0);
      EXPECT_EQ(rows.state[r], rows.kind[r] == RowKind::Normal ? RowState::Lower : RowState::Free);
      continue;
    }
    const int old = row_with_key(solved, rows.key[r]);
    EXPECT_EQ(rows.state[r], solved.state[old]);
    if (rows.kind[r] != RowKind::Friction) EXPECT_EQ(rows.lambda[r], solved.lambda[old]);
  }
  const Vec3 f5 = friction(solved, 5), f9 = friction(solved, 9);
  EXPECT_LE((friction(rows, 5) - f5).norm(), 8 * kEps * f5.norm());
  EXPECT_LE((friction(rows, 9) - (f9 - f9.dot(tilted) * tilted)).norm(), 8 * kEps * f9.norm());
  // The tangents did turn: the rows' own impulses are not the old ones.
  const int r5 = row_with_key(rows, contact_row_key(5, 1));
  EXPECT_GT(std::abs(rows.lambda[r5] - solved.lambda[row_with_key(solved, contact_row_key(5, 1))]), 1e-3);
}

// Ball joint between box 1 and box 2 (or the world, or a static body), its anchor fixed in each
// body's frame at the start; then the bodies move and turn.
struct Jointed {
  Bodies bodies;
  JointDef def;
  Vec3 local[2];  // the anchor in each dynamic body's frame, by hand
  Jointed(JointType type, int body_b) {
    add_static(bodies, Vec3(0, 0, -1));
    add_box(bodies, 2.0, Vec3(0.3, 0.2, 0.1), Vec3(0.1, 0.2, 0.3), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())));
    add_box(bodies, 7.0, Vec3(0.2, 0.2, 0.4), Vec3(0.4, -0.1, 0.9), Quat(Eigen::AngleAxisd(-1.1, Vec3(-2, 1, 1).normalized())));
    def.type = type;
    def.body_a = 1;
    def.body_b = body_b;
    def.anchor = Vec3(0.3, 0.0, 0.6);
    def.axis = Vec3(1, 1, 0);
    for (int s : {1, 2}) local[s - 1] = bodies.q[s].conjugate() * (def.anchor - bodies.x[s]);
  }
  std::vector<JointFrame> frames() const {
    SceneDef scene;
    scene.joints = {def};
    return make_joint_frames(scene, bodies);
  }
  void move(int k, const Vec3& dx, const Quat& turn) {
    bodies.x[k] += dx;
    bodies.q[k] = turn * bodies.q[k];
  }
  Vec3 anchor(int s) const {
    const int k = s == 0 ? def.body_a : def.body_b;
    return k >= 0 && !bodies.is_static[k] ? Vec3(bodies.x[k] + bodies.q[k] * local[k - 1]) : def.anchor;
  }
};

TEST(Assemble, BallJointRowsMeasureTheAnchorsRelativeVelocityAndDrift) {
  // Rows d = x, y, z: J u = e_d . (v_a + w_a x r_a - v_b - w_b x r_b) at the anchors, and
  // q - J u = (erp/h) e_d . (p_a - p_b), the drift of the anchors the bodies carry.
  StepParams params;
  for (int body_b : {2, 0, -1}) {
    SCOPED_TRACE(body_b);
    Jointed s(JointType::Ball, body_b);
    const std::vector<JointFrame> frames = s.frames();
    s.move(1, Vec3(0.01, -0.02, 0.005), Quat(Eigen::AngleAxisd(0.05, Vec3(0, 1, 1).normalized())));
    s.move(2, Vec3(-0.003, 0.0, 0.01), Quat(Eigen::AngleAxisd(0.02, Vec3(1, 0, 0))));
    std::mt19937 rng(6);
    randomise_velocities(s.bodies, rng);
    Rows rows;
    assemble({}, frames, s.bodies, params, rows);
    ASSERT_EQ(rows.size(), 3u);
    const int b = body_b == 2 ? 2 : -1;
    const Vec3 pa = s.anchor(0), pb = s.anchor(1);
    const Vec3 relative = point_velocity(s.bodies, 1, pa) - (b >= 0 ? point_velocity(s.bodies, b, pb) : Vec3::Zero());
    for (int d = 0; d < 3; ++d) {
      EXPECT_EQ(rows.key[d], joint_row_key(0, d));
      EXPECT_EQ(rows.kind[d], RowKind::Joint);
      EXPECT_EQ(rows.body[d][0], 1);
      EXPECT_EQ(rows.body[d][1], b);
      EXPECT_EQ(rows.lo[d], -kInf);
      EXPECT_EQ(rows.hi[d], kInf);
      double scale;
      const double ju = row_times(rows, d, s.bodies, &scale);
      EXPECT_NEAR(ju, relative[d], 16 * kEps * scale);
      const double drift = params.erp / kStep * (pa - pb)[d];
      EXPECT_NEAR(rows.q[d] - ju, drift, 16 * kEps * (scale + params.erp / kStep * 2));
    }
  }
}

TEST(Assemble, JointBetweenStaticBodiesHasNoRows) {
  Bodies b;
  add_static(b, Vec3(0, 0, -1));
  add_static(b, Vec3(0, 0, 1));
  JointDef def;
  def.body_a = 0;
  def.body_b = 1;
  SceneDef scene;
  scene.joints = {def};
  Rows rows;
  assemble({}, make_joint_frames(scene, b), b, StepParams{}, rows);
  EXPECT_EQ(rows.size(), 0u);
}

// The angular rows (those after the three point rows): sum_k phi_k d_k for their directions d_k
// and position errors phi_k = (q_k - J_k u) h / erp.
Vec3 angular_error(const Rows& rows, const Bodies& b, const StepParams& params) {
  Vec3 e = Vec3::Zero();
  for (int r = 3; r < static_cast<int>(rows.size()); ++r) {
    EXPECT_TRUE(rows.jac[r][0].head<3>().isZero());
    EXPECT_EQ(rows.jac[r][1], Vec6(-rows.jac[r][0]));
    e += (rows.q[r] - row_times(rows, r, b)) * kStep / params.erp * rows.jac[r][0].tail<3>();
  }
  return e;
}

TEST(Assemble, HingeRowsLeaveOnlyTheTurnAboutTheAxis) {
  // Two angular rows along unit directions perpendicular to the hinge axis a: relative angular
  // velocity along a is free (J u = 0), across it fully measured (sum (J u)^2 = |w_perp|^2). Body a
  // turned by theta about u perpendicular to a: the error is a_b x a_a = sin(theta) u.
  StepParams params;
  Jointed s(JointType::Hinge, 2);
  const std::vector<JointFrame> frames = s.frames();
  const Vec3 axis = s.def.axis.normalized();
  const Vec3 across = axis.cross(Vec3::UnitZ()).normalized();
  const double theta = 0.2;
  s.move(1, Vec3::Zero(), Quat(Eigen::AngleAxisd(theta, across)));
  Rows rows;
  assemble({}, frames, s.bodies, params, rows);
  ASSERT_EQ(rows.size(), 5u);
  const Vec3 axis_a = Quat(Eigen::AngleAxisd(theta, across)) * axis;
  for (const Vec3& w : {Vec3(axis_a), Vec3(axis_a.cross(across)), Vec3(1, -2, 0.5)}) {
    s.bodies.w[1] = w;
    double squares = 0;
    for (int r = 3; r < 5; ++r) squares += std::pow(row_times(rows, r, s.bodies), 2);
    const Vec3 perpendicular = w - w.dot(axis_a) * axis_a;
    EXPECT_NEAR(squares, perpendicular.squaredNorm(), 16 * kEps * w.squaredNorm());
  }
  s.bodies.w[1].setZero();
  EXPECT_LE((angular_error(rows, s.bodies, params) - std::sin(theta) * across).norm(), 64 * kEps);
}

TEST(Assemble, FixedJointRowsMeasureTheRelativeTurn) {
  // Three angular rows: J u = (w_a - w_b)_d. Body a turned by theta about e from the rest pose gives
  // the error 2 sin(theta/2) e (the rotation vector to second order); both bodies turned alike
  // give none.
  StepParams params;
  const Vec3 e = Vec3(1, -1, 2).normalized();
  const double theta = 0.3;
  Jointed s(JointType::Fixed, 2);
  const std::vector<JointFrame> frames = s.frames();
  s.move(1, Vec3::Zero(), Quat(Eigen::AngleAxisd(theta, e)));
  std::mt19937 rng(8);
  randomise_velocities(s.bodies, rng);
  Rows rows;
  assemble({}, frames, s.bodies, params, rows);
  ASSERT_EQ(rows.size(), 6u);
  const Vec3 relative = s.bodies.w[1] - s.bodies.w[2];
  for (int d = 0; d < 3; ++d) {
    double scale;
    EXPECT_NEAR(row_times(rows, 3 + d, s.bodies, &scale), relative[d], 16 * kEps * scale);
  }
  EXPECT_LE((angular_error(rows, s.bodies, params) - 2 * std::sin(theta / 2) * e).norm(), 256 * kEps);

  Jointed t(JointType::Fixed, 2);
  const std::vector<JointFrame> rest = t.frames();
  const Quat turn(Eigen::AngleAxisd(0.9, Vec3(0.2, 1, 0).normalized()));
  t.move(1, Vec3::Zero(), turn);
  t.move(2, Vec3::Zero(), turn);
  assemble({}, rest, t.bodies, params, rows);
  EXPECT_LE(angular_error(rows, t.bodies, params).norm(), 256 * kEps);
}

// The contacts are assembled in parallel, each into its own rows: the rows are the same bit for bit
// on one thread and on several, warm started or not, with joints after the contacts.
TEST(Assemble, RowsAreTheSameOnAnyNumberOfThreads) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  Bodies b;
  add_static(b, Vec3(0, 0, -1));
  for (int k = 0; k < 40; ++k)
    add_box(b, 1.0 + k, Vec3(0.2, 0.3, 0.1), Vec3(u(rng), u(rng), u(rng)),
            Quat(Eigen::AngleAxisd(3 * u(rng), Vec3(u(rng), u(rng), 1).normalized())), 0.3 + 0.2 * u(rng));
  randomise_velocities(b, rng);
  std::vector<Contact> contacts;
  for (std::uint64_t id = 0; id < 3000; ++id) {
    const int a = 1 + static_cast<int>(rng() % 40), other = static_cast<int>(rng() % 41);
    contacts.push_back(contact(a, other == a ? 0 : other, Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), 1),
                               0.01 * u(rng), id));
  }
  JointDef def;
  def.body_a = 1;
  def.body_b = 2;
  def.anchor = Vec3(0.1, 0.2, 0.3);
  SceneDef scene;
  scene.joints = {def};
  const std::vector<JointFrame> joints = make_joint_frames(scene, b);
  const auto in_arena = [&](int threads, const WarmStart& warm) {
    Rows rows;
    tbb::task_arena(threads).execute([&] { assemble(contacts, joints, b, StepParams{}, rows, warm); });
    return rows;
  };
  const auto expect_same = [](const Rows& x, const Rows& y) {
    ASSERT_EQ(x.size(), y.size());
    EXPECT_EQ(x.body, y.body);
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_EQ(x.normal_of, y.normal_of);
    EXPECT_EQ(x.key, y.key);
    EXPECT_EQ(x.state, y.state);
    for (std::size_t r = 0; r < x.size(); ++r) {
      ASSERT_TRUE(x.jac[r][0] == y.jac[r][0] && x.jac[r][1] == y.jac[r][1]) << "row " << r;
      for (const auto field : {&Rows::q, &Rows::lo, &Rows::hi, &Rows::sigma, &Rows::mu, &Rows::lambda})
        ASSERT_EQ(std::memcmp(&((x.*field)[r]), &((y.*field)[r]), sizeof(double)), 0) << "row " << r;
    }
  };
  Rows serial = in_arena(1, WarmStart{});
  ASSERT_EQ(serial.size(), 3 * contacts.size() + 3);
  expect_same(serial, in_arena(3, WarmStart{}));
  // Warm started from impulses and states of the rows above, every other contact gone.
  const RowState states[] = {RowState::Free, RowState::Lower, RowState::Upper};
  for (std::size_t r = 0; r < serial.size(); ++r) {
    serial.lambda[r] = u(rng);
    serial.state[r] = states[rng() % 3];
  }
  WarmStart warm;
  warm.store(serial);
  for (std::size_t k = 0; k < contacts.size() / 2; ++k) contacts[k] = contacts[2 * k];
  contacts.resize(contacts.size() / 2);
  const Rows warm_serial = in_arena(1, warm);
  expect_same(warm_serial, in_arena(3, warm));
  int warmed = 0;
  for (std::size_t r = 0; r < warm_serial.size(); ++r) warmed += warm_serial.lambda[r] != 0;
  EXPECT_GT(warmed, static_cast<int>(warm_serial.size()) / 2);
}

}  // namespace
}  // namespace rbpart
