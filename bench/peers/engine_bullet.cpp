// Bullet 3.24 in double precision (Debian's -float64 libraries): the sequential-impulse solver
// ("si") or btMLCPSolver with btDantzigSolver ("mlcp"). Persistent manifolds hold at most four
// points per pair; friction sqrt(mu) per body, which Bullet multiplies into mu per pair.
#include <BulletDynamics/MLCPSolvers/btDantzigSolver.h>
#include <BulletDynamics/MLCPSolvers/btMLCPSolver.h>
#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "peers.hpp"

namespace peers {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

Vec3 v3(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

// Times every solveGroup call and, before the solver writes its velocities back, reads the rows
// it solved: the same row data its iterations (or the MLCP built from them) use.
template <class Base>
class Measured : public Base {
 public:
  using Base::Base;
  double solve_ms = 0;
  std::vector<Row>* rows = nullptr;  // null: no residual
  const std::unordered_map<const btRigidBody*, int>* nodes = nullptr;

  btScalar solveGroup(btCollisionObject** bodies, int num_bodies, btPersistentManifold** manifolds, int num_manifolds,
                      btTypedConstraint** constraints, int num_constraints, const btContactSolverInfo& info,
                      btIDebugDraw* debug, btDispatcher* dispatcher) override {
    const auto start = Clock::now();
    const btScalar r = Base::solveGroup(bodies, num_bodies, manifolds, num_manifolds, constraints, num_constraints, info,
                                        debug, dispatcher);
    solve_ms += ms_since(start);
    return r;
  }

 protected:
  btScalar solveGroupCacheFriendlyFinish(btCollisionObject** bodies, int num_bodies,
                                         const btContactSolverInfo& info) override {
    if (rows) {
      collect(this->m_tmpSolverNonContactConstraintPool, false);
      collect(this->m_tmpSolverContactConstraintPool, false);
      collect(this->m_tmpSolverContactFrictionConstraintPool, true);
    }
    return Base::solveGroupCacheFriendlyFinish(bodies, num_bodies, info);
  }

 private:
  int node(const btSolverBody& b) const {
    if (!b.m_originalBody) return -1;
    const auto it = nodes->find(b.m_originalBody);
    return it == nodes->end() ? -1 : it->second;
  }

  // A Gauss-Seidel update of a row is  rhs - cfm lambda - jacDiagABInv J dv  (dv: the solver
  // bodies' velocity change so far), that is -w_j / A_jj with A_jj = 1 / jacDiagABInv; the free
  // term is q_j = -rhs_j / jacDiagABInv. Friction is bounded by mu times its normal's impulse.
  void collect(btConstraintArray& pool, bool friction) {
    for (int i = 0; i < pool.size(); ++i) {
      const btSolverConstraint& c = pool[i];
      btSolverBody& a = this->m_tmpSolverBodyPool[c.m_solverBodyIdA];
      btSolverBody& b = this->m_tmpSolverBodyPool[c.m_solverBodyIdB];
      const double jdv = c.m_contactNormal1.dot(a.internalGetDeltaLinearVelocity()) +
                         c.m_relpos1CrossNormal.dot(a.internalGetDeltaAngularVelocity()) +
                         c.m_contactNormal2.dot(b.internalGetDeltaLinearVelocity()) +
                         c.m_relpos2CrossNormal.dot(b.internalGetDeltaAngularVelocity());
      if (c.m_jacDiagABInv == 0) continue;
      Row row;
      row.node_a = node(a);
      row.node_b = node(b);
      row.lambda = c.m_appliedImpulse;
      row.a_jj = 1 / c.m_jacDiagABInv;
      row.q = -c.m_rhs / c.m_jacDiagABInv;
      row.inner = row.lambda + c.m_rhs - c.m_cfm * row.lambda - c.m_jacDiagABInv * jdv;
      if (friction) {
        const double normal = this->m_tmpSolverContactConstraintPool[c.m_frictionIndex].m_appliedImpulse;
        row.hi = c.m_friction * std::max(0.0, normal);
        row.lo = -row.hi;
      } else {
        row.lo = c.m_lowerLimit;
        row.hi = c.m_upperLimit;
      }
      rows->push_back(row);
    }
  }
};

class BulletEngine final : public Engine {
 public:
  BulletEngine(const Scene& scene, const std::string& solver, bool residual) : scene_(scene), mlcp_(solver == "mlcp") {
    if (solver != "si" && solver != "mlcp") throw std::runtime_error("bullet: solver is si or mlcp");
    dispatcher_ = std::make_unique<btCollisionDispatcher>(&config_);
    if (mlcp_) {
      auto s = std::make_unique<Measured<btMLCPSolver>>(&dantzig_);
      mlcp_solver_ = s.get();
      solver_ = std::move(s);
    } else {
      auto s = std::make_unique<Measured<btSequentialImpulseConstraintSolver>>();
      si_solver_ = s.get();
      solver_ = std::move(s);
    }
    world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), &broadphase_, solver_.get(), &config_);
    world_->setGravity(btVector3(scene.gravity[0], scene.gravity[1], scene.gravity[2]));
    // As Bullet's own MLCP example: a direct solver is better fed island by island.
    if (mlcp_) world_->getSolverInfo().m_minimumSolverBatchSize = 1;
    for (size_t i = 0; i < scene.bodies.size(); ++i) add_body(i);
    for (const auto& j : scene.joints) {
      btRigidBody* a = bodies_[j.a].get();
      const btVector3 anchor(j.anchor[0], j.anchor[1], j.anchor[2]);
      const btVector3 in_a = a->getCenterOfMassTransform().inverse() * anchor;
      std::unique_ptr<btPoint2PointConstraint> c;
      if (j.b >= 0) {
        btRigidBody* b = bodies_[j.b].get();
        c = std::make_unique<btPoint2PointConstraint>(*a, *b, in_a, b->getCenterOfMassTransform().inverse() * anchor);
      } else {
        c = std::make_unique<btPoint2PointConstraint>(*a, in_a);
      }
      world_->addConstraint(c.get(), /*disableCollisionsBetweenLinkedBodies=*/true);
      joints_.push_back(std::move(c));
    }
    if (residual) {
      if (si_solver_) si_solver_->rows = &rows_, si_solver_->nodes = &nodes_;
      if (mlcp_solver_) mlcp_solver_->rows = &rows_, mlcp_solver_->nodes = &nodes_;
    }
    residual_ = residual;
  }

  ~BulletEngine() override {
    for (auto& j : joints_) world_->removeConstraint(j.get());
    for (auto& b : bodies_) world_->removeRigidBody(b.get());
  }

  StepReport step() override {
    StepReport report;
    rows_.clear();
    double& solve_ms = si_solver_ ? si_solver_->solve_ms : mlcp_solver_->solve_ms;
    solve_ms = 0;
    const auto start = Clock::now();
    world_->stepSimulation(scene_.dt, 0);
    report.total_ms = ms_since(start);
    report.solve_ms = solve_ms;
    for (int m = 0; m < dispatcher_->getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher_->getManifoldByIndexInternal(m);
      report.contacts += manifold->getNumContacts();
      for (int k = 0; k < manifold->getNumContacts(); ++k)
        report.max_penetration = std::max(report.max_penetration, -double(manifold->getContactPoint(k).getDistance()));
    }
    if (residual_) report.blcp_residual = natural_map_residual(rows_, static_cast<int>(bodies_.size()));
    return report;
  }

  std::vector<BodyState> state() const override {
    std::vector<BodyState> out;
    for (const auto& b : bodies_) {
      const btTransform& t = b->getCenterOfMassTransform();
      const btQuaternion q = t.getRotation();
      out.push_back({v3(t.getOrigin()), {q.w(), q.x(), q.y(), q.z()}, v3(b->getLinearVelocity()), v3(b->getAngularVelocity())});
    }
    return out;
  }

  std::string settings_json() const override {
    const btContactSolverInfo& s = world_->getSolverInfo();
    std::ostringstream o;
    o << "{\"engine\": \"Bullet " << btGetVersion() << "\", \"precision\": \""
      << (sizeof(btScalar) == 8 ? "double" : "single") << "\", \"solver\": \""
      << (mlcp_ ? "btMLCPSolver(btDantzigSolver)" : "btSequentialImpulseConstraintSolver")
      << "\", \"num_iterations\": " << s.m_numIterations << ", \"erp\": " << s.m_erp << ", \"erp2\": " << s.m_erp2
      << ", \"global_cfm\": " << s.m_globalCfm << ", \"sor\": " << s.m_sor << ", \"split_impulse\": " << s.m_splitImpulse
      << ", \"split_impulse_penetration_threshold\": " << s.m_splitImpulsePenetrationThreshold
      << ", \"linear_slop\": " << s.m_linearSlop << ", \"warmstarting_factor\": " << s.m_warmstartingFactor
      << ", \"solver_mode\": " << s.m_solverMode << ", \"two_friction_directions\": "
      << ((s.m_solverMode & SOLVER_USE_2_FRICTION_DIRECTIONS) ? 1 : 0)
      << ", \"minimum_solver_batch_size\": " << s.m_minimumSolverBatchSize
      << ", \"restitution\": 0, \"max_points_per_pair\": " << MANIFOLD_CACHE_SIZE
      << ", \"contact_breaking_threshold\": " << gContactBreakingThreshold
      << ", \"box_margin\": " << (box_margin_ < 0 ? 0.0 : box_margin_)
      << ", \"mlcp_fallbacks\": " << (mlcp_solver_ ? mlcp_solver_->getNumFallbacks() : 0)
      << ", \"deactivation\": \"disabled\", \"friction\": \"sqrt(mu) per body, multiplied per pair\""
      << ", \"broad_phase\": \"btDbvtBroadphase\"}";
    return o.str();
  }

 private:
  void add_body(size_t i) {
    const Body& b = scene_.bodies[i];
    std::unique_ptr<btCollisionShape> shape;
    switch (b.shape.type) {
      case ShapeType::box:
        shape = std::make_unique<btBoxShape>(btVector3(b.shape.half_extents[0], b.shape.half_extents[1], b.shape.half_extents[2]));
        box_margin_ = shape->getMargin();
        break;
      case ShapeType::sphere: shape = std::make_unique<btSphereShape>(b.shape.radius); break;
      case ShapeType::capsule: shape = std::make_unique<btCapsuleShapeZ>(b.shape.radius, 2 * b.shape.half_length); break;
    }
    btTransform t(btQuaternion(b.orientation[1], b.orientation[2], b.orientation[3], b.orientation[0]),
                  btVector3(b.position[0], b.position[1], b.position[2]));
    const double mass = b.is_static ? 0 : b.mass;
    const btVector3 inertia = b.is_static ? btVector3(0, 0, 0) : btVector3(b.inertia[0], b.inertia[1], b.inertia[2]);
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape.get(), inertia);
    info.m_startWorldTransform = t;
    info.m_friction = std::sqrt(b.friction);
    info.m_restitution = 0;
    auto body = std::make_unique<btRigidBody>(info);
    body->setActivationState(DISABLE_DEACTIVATION);
    if (!b.is_static) {
      body->setLinearVelocity(btVector3(b.velocity[0], b.velocity[1], b.velocity[2]));
      body->setAngularVelocity(btVector3(b.angular_velocity[0], b.angular_velocity[1], b.angular_velocity[2]));
      nodes_[body.get()] = static_cast<int>(i);
    }
    world_->addRigidBody(body.get());
    shapes_.push_back(std::move(shape));
    bodies_.push_back(std::move(body));
  }

  const Scene& scene_;
  bool mlcp_, residual_ = false;
  double box_margin_ = -1;
  btDefaultCollisionConfiguration config_;
  btDbvtBroadphase broadphase_;
  btDantzigSolver dantzig_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btConstraintSolver> solver_;
  Measured<btSequentialImpulseConstraintSolver>* si_solver_ = nullptr;
  Measured<btMLCPSolver>* mlcp_solver_ = nullptr;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<std::unique_ptr<btPoint2PointConstraint>> joints_;
  std::unordered_map<const btRigidBody*, int> nodes_;
  std::vector<Row> rows_;
};

}  // namespace

std::unique_ptr<Engine> make_bullet(const Scene& scene, const std::string& solver, bool residual) {
  return std::make_unique<BulletEngine>(scene, solver, residual);
}

}  // namespace peers
