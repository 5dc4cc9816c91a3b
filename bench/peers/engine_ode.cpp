// ODE 0.16: dWorldStep (dense Dantzig LCP, solver "dantzig") or dWorldQuickStep (PGS, "quickstep").
// Contacts: at most four points per pair (dCollide's count), friction pyramid bounded by mu times
// the normal force of the same solve (dContactApprox1), no bounce, the engine's ERP/CFM.
#include <ode/ode.h>

#include <chrono>
#include <cmath>
#include <deque>
#include <sstream>
#include <stdexcept>

#include "peers.hpp"

namespace peers {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

Vec3 v3(const dReal* p) { return {p[0], p[1], p[2]}; }

constexpr int kMaxPoints = 4;

class OdeEngine final : public Engine {
 public:
  OdeEngine(const Scene& scene, const std::string& solver, bool residual)
      : scene_(scene), quick_(solver == "quickstep"), residual_(residual) {
    if (solver != "dantzig" && solver != "quickstep") throw std::runtime_error("ode: solver is dantzig or quickstep");
    dInitODE2(0);
    dAllocateODEDataForThread(dAllocateMaskAll);
    world_ = dWorldCreate();
    space_ = dHashSpaceCreate(nullptr);
    contacts_ = dJointGroupCreate(0);
    dWorldSetGravity(world_, scene.gravity[0], scene.gravity[1], scene.gravity[2]);
    dWorldSetAutoDisableFlag(world_, 0);
    for (size_t i = 0; i < scene.bodies.size(); ++i) add_body(i);
    for (const auto& j : scene.joints) {
      dJointID joint = dJointCreateBall(world_, nullptr);
      dJointAttach(joint, bodies_[j.a], j.b >= 0 ? bodies_[j.b] : nullptr);
      dJointSetBallAnchor(joint, j.anchor[0], j.anchor[1], j.anchor[2]);
      joints_.push_back({joint, j.a, j.b, {}});
      dJointSetFeedback(joint, &joints_.back().feedback);
    }
  }

  ~OdeEngine() override {
    dJointGroupDestroy(contacts_);
    dSpaceDestroy(space_);
    dWorldDestroy(world_);
    dCloseODE();
  }

  StepReport step() override {
    StepReport report;
    const auto start = Clock::now();
    dJointGroupEmpty(contacts_);
    points_.clear();
    dSpaceCollide(space_, this, &OdeEngine::near_callback);
    std::vector<Mat3> rotations;
    std::vector<Vec3> centres;
    if (residual_) {
      // The solve uses the inertia at the orientation before the step, and the Jacobian at the
      // positions before it.
      for (size_t i = 0; i < bodies_.size(); ++i) {
        rotations.push_back(bodies_[i] ? rotation(quat(bodies_[i])) : Mat3{});
        centres.push_back(bodies_[i] ? v3(dBodyGetPosition(bodies_[i])) : Vec3{});
      }
      for (auto& j : joints_) {
        dVector3 a1, a2;
        dJointGetBallAnchor(j.joint, a1);
        dJointGetBallAnchor2(j.joint, a2);
        j.separation = sub(v3(a2), v3(a1));
        j.anchor_a = v3(a1);
        j.anchor_b = v3(a2);
      }
    }
    const auto solve_start = Clock::now();
    if (quick_) dWorldQuickStep(world_, scene_.dt);
    else dWorldStep(world_, scene_.dt);
    report.solve_ms = ms_since(solve_start);
    report.total_ms = ms_since(start);
    report.contacts = static_cast<int>(points_.size());
    for (const auto& p : points_) report.max_penetration = std::max(report.max_penetration, p.depth);
    if (residual_) report.blcp_residual = residual(rotations, centres);
    return report;
  }

  std::vector<BodyState> state() const override {
    std::vector<BodyState> out;
    for (size_t i = 0; i < bodies_.size(); ++i) {
      BodyState s;
      if (bodies_[i]) {
        s.position = v3(dBodyGetPosition(bodies_[i]));
        s.orientation = quat(bodies_[i]);
        s.velocity = v3(dBodyGetLinearVel(bodies_[i]));
        s.angular_velocity = v3(dBodyGetAngularVel(bodies_[i]));
      } else {
        s.position = scene_.bodies[i].position;
        s.orientation = scene_.bodies[i].orientation;
      }
      out.push_back(s);
    }
    return out;
  }

  std::string settings_json() const override {
    std::ostringstream o;
    o << "{\"engine\": \"ODE " << dGetConfiguration() << "\", \"stepper\": \""
      << (quick_ ? "dWorldQuickStep" : "dWorldStep") << "\", \"precision\": \""
      << (dCheckConfiguration("ODE_double_precision") ? "double" : "single")
      << "\", \"erp\": " << dWorldGetERP(world_) << ", \"cfm\": " << dWorldGetCFM(world_)
      << ", \"contact_max_correcting_vel\": " << json_number(dWorldGetContactMaxCorrectingVel(world_))
      << ", \"contact_surface_layer\": " << dWorldGetContactSurfaceLayer(world_)
      << ", \"quickstep_iterations\": " << dWorldGetQuickStepNumIterations(world_)
      << ", \"quickstep_sor_w\": " << dWorldGetQuickStepW(world_)
      << ", \"auto_disable\": " << dWorldGetAutoDisableFlag(world_)
      << ", \"max_points_per_pair\": " << kMaxPoints
      << ", \"contact_mode\": \"dContactApprox1 | dContactFDir1 (friction pyramid, bounds mu * normal force)\""
      << ", \"friction\": \"sqrt(mu_a mu_b) per contact\", \"broad_phase\": \"dHashSpace\"}";
    return o.str();
  }

 private:
  struct Point {  // one contact joint; body a dynamic, b dynamic or -1
    int a, b;
    Vec3 pos, normal, t1, t2;
    double depth, mu;
    dJointFeedback feedback;
  };
  struct BallJoint {
    dJointID joint;
    int a, b;
    dJointFeedback feedback;
    Vec3 separation{}, anchor_a{}, anchor_b{};
  };

  static Quat quat(dBodyID body) {
    const dReal* q = dBodyGetQuaternion(body);
    return {q[0], q[1], q[2], q[3]};
  }

  void add_body(size_t i) {
    const Body& b = scene_.bodies[i];
    dGeomID geom = nullptr;
    switch (b.shape.type) {
      case ShapeType::box:
        geom = dCreateBox(space_, 2 * b.shape.half_extents[0], 2 * b.shape.half_extents[1], 2 * b.shape.half_extents[2]);
        break;
      case ShapeType::sphere: geom = dCreateSphere(space_, b.shape.radius); break;
      case ShapeType::capsule: geom = dCreateCapsule(space_, b.shape.radius, 2 * b.shape.half_length); break;
    }
    dQuaternion q = {b.orientation[0], b.orientation[1], b.orientation[2], b.orientation[3]};
    dBodyID body = nullptr;
    if (!b.is_static) {
      body = dBodyCreate(world_);
      dMass mass;
      dMassSetParameters(&mass, b.mass, 0, 0, 0, b.inertia[0], b.inertia[1], b.inertia[2], 0, 0, 0);
      dBodySetMass(body, &mass);
      dBodySetPosition(body, b.position[0], b.position[1], b.position[2]);
      dBodySetQuaternion(body, q);
      dBodySetLinearVel(body, b.velocity[0], b.velocity[1], b.velocity[2]);
      dBodySetAngularVel(body, b.angular_velocity[0], b.angular_velocity[1], b.angular_velocity[2]);
      dGeomSetBody(geom, body);
    } else {
      dGeomSetPosition(geom, b.position[0], b.position[1], b.position[2]);
      dGeomSetQuaternion(geom, q);
    }
    dGeomSetData(geom, reinterpret_cast<void*>(i));
    bodies_.push_back(body);
  }

  static void near_callback(void* self, dGeomID g1, dGeomID g2) { static_cast<OdeEngine*>(self)->collide(g1, g2); }

  void collide(dGeomID g1, dGeomID g2) {
    dBodyID b1 = dGeomGetBody(g1), b2 = dGeomGetBody(g2);
    if (!b1 && !b2) return;
    if (b1 && b2 && dAreConnectedExcluding(b1, b2, dJointTypeContact)) return;
    const bool swap = b1 == nullptr;  // the dynamic body first, so the feedback's f1 is its force
    if (swap) std::swap(g1, g2), std::swap(b1, b2);
    dContactGeom geoms[kMaxPoints];
    const int n = dCollide(g1, g2, kMaxPoints, geoms, sizeof(dContactGeom));
    const int ia = static_cast<int>(reinterpret_cast<size_t>(dGeomGetData(g1)));
    const int ib = static_cast<int>(reinterpret_cast<size_t>(dGeomGetData(g2)));
    const double mu = pair_friction(scene_.bodies[ia], scene_.bodies[ib]);
    for (int k = 0; k < n; ++k) {
      dContact c{};
      c.geom = geoms[k];
      c.surface.mode = dContactApprox1 | dContactFDir1;
      c.surface.mu = mu;
      dVector3 t1, t2;
      dPlaneSpace(c.geom.normal, t1, t2);
      dCopyVector3(c.fdir1, t1);
      // As ODE's contact joint: the second direction is normal x fdir1.
      const Vec3 normal = v3(c.geom.normal), d1 = v3(t1);
      points_.push_back({ia, b2 ? ib : -1, v3(c.geom.pos), normal, d1, cross(normal, d1), c.geom.depth, mu, {}});
      dJointID joint = dJointCreateContact(world_, contacts_, &c);
      dJointAttach(joint, b1, b2);
      dJointSetFeedback(joint, &points_.back().feedback);
    }
  }

  // The LCP dWorldStep/QuickStep solved, in impulse units (Lambda = h lambda): rows J with
  // A = J M^-1 J^T + cfm/h, q = J v_free - c, w = A Lambda + q = J v+ - c + (cfm/h) Lambda.
  double residual(const std::vector<Mat3>& rotations, const std::vector<Vec3>& centres) const {
    const double h = scene_.dt, cfm = dWorldGetCFM(world_) / h, erp = dWorldGetERP(world_);
    const double layer = dWorldGetContactSurfaceLayer(world_), max_vel = dWorldGetContactMaxCorrectingVel(world_);
    struct Jrow { int a, b; Vec3 la, aa, lb, ab; double c, lambda, lo, hi; int normal; };
    std::vector<Jrow> rows;
    auto push = [&](int a, int b, const Vec3& d, const Vec3& ra, const Vec3& rb, double c, const Vec3& force_on_a,
                    double lo, double hi, int normal) {
      rows.push_back({a, b, d, cross(ra, d), scale(d, -1), scale(cross(rb, d), -1), c, h * dot(force_on_a, d), lo, hi, normal});
    };
    for (const auto& p : points_) {
      const Vec3 ra = sub(p.pos, centres[p.a]), rb = p.b >= 0 ? sub(p.pos, centres[p.b]) : Vec3{};
      const Vec3 f1 = v3(p.feedback.f1);
      const double c = std::min(erp / h * std::max(0.0, p.depth - layer), max_vel);
      const int n = static_cast<int>(rows.size());
      push(p.a, p.b, p.normal, ra, rb, c, f1, 0, INFINITY, -1);
      push(p.a, p.b, p.t1, ra, rb, 0, f1, 0, 0, n);
      push(p.a, p.b, p.t2, ra, rb, 0, f1, 0, 0, n);
      rows[n + 1].hi = rows[n + 2].hi = p.mu;  // a coefficient until the normal impulse is known
    }
    for (const auto& j : joints_) {
      const Vec3 f1 = v3(j.feedback.f1);
      for (int k = 0; k < 3; ++k) {
        Vec3 d{};
        d[k] = 1;
        push(j.a, j.b, d, sub(j.anchor_a, centres[j.a]), j.b >= 0 ? sub(j.anchor_b, centres[j.b]) : Vec3{},
             erp / h * j.separation[k], f1, -INFINITY, INFINITY, -1);
      }
    }
    // dv = M^-1 J^T Lambda, with the inertia of the orientation the solve used.
    const size_t nb = bodies_.size();
    std::vector<Vec3> dv(nb), dw(nb);
    auto apply = [&](int body, const Vec3& lin, const Vec3& ang, double lambda) {
      if (body < 0) return;
      const Body& b = scene_.bodies[body];
      dv[body] = add(dv[body], scale(lin, lambda / b.mass));
      dw[body] = add(dw[body], world_inverse_inertia_times(rotations[body], b.inertia, scale(ang, lambda)));
    };
    for (const auto& r : rows) apply(r.a, r.la, r.aa, r.lambda), apply(r.b, r.lb, r.ab, r.lambda);
    std::vector<Row> out;
    for (const auto& r : rows) {
      auto jv = [&](int body, const Vec3& lin, const Vec3& ang, bool after) {
        if (body < 0) return 0.0;
        Vec3 v = v3(dBodyGetLinearVel(bodies_[body])), w = v3(dBodyGetAngularVel(bodies_[body]));
        if (!after) v = sub(v, dv[body]), w = sub(w, dw[body]);
        return dot(lin, v) + dot(ang, w);
      };
      auto diag = [&](int body, const Vec3& lin, const Vec3& ang) {
        if (body < 0) return 0.0;
        const Body& b = scene_.bodies[body];
        return dot(lin, lin) / b.mass + dot(ang, world_inverse_inertia_times(rotations[body], b.inertia, ang));
      };
      Row row;
      row.node_a = r.a;
      row.node_b = r.b;
      row.lambda = r.lambda;
      row.a_jj = diag(r.a, r.la, r.aa) + diag(r.b, r.lb, r.ab) + cfm;
      const double w = jv(r.a, r.la, r.aa, true) + jv(r.b, r.lb, r.ab, true) - r.c + cfm * r.lambda;
      row.q = jv(r.a, r.la, r.aa, false) + jv(r.b, r.lb, r.ab, false) - r.c;
      row.inner = r.lambda - w / row.a_jj;
      row.lo = r.lo;
      row.hi = r.hi;
      if (r.normal >= 0) {
        row.hi = r.hi * std::max(0.0, rows[r.normal].lambda);
        row.lo = -row.hi;
      }
      out.push_back(row);
    }
    return natural_map_residual(out, static_cast<int>(nb));
  }

  const Scene& scene_;
  bool quick_, residual_;
  dWorldID world_;
  dSpaceID space_;
  dJointGroupID contacts_;
  std::vector<dBodyID> bodies_;
  std::deque<BallJoint> joints_;  // deques: the feedback addresses stay put
  std::deque<Point> points_;
};

}  // namespace

std::unique_ptr<Engine> make_ode(const Scene& scene, const std::string& solver, bool residual) {
  return std::make_unique<OdeEngine>(scene, solver, residual);
}

}  // namespace peers
