// Collision stage (docs/pipeline.md#collide): the Collider on the two parts of Bullet's collision
// module that it uses, in double precision; the contact points are rbpart's own (narrow_phase.hpp).
// Besides geometry/hull.cpp (btConvexHullComputer), the only file that includes Bullet.
//
// - Broad phase: btDbvtBroadphase inside a btCollisionWorld. AABBs are set here, each grown by half
//   the contact margin plus the body's own sweep, so the boxes of every pair closer than its margin
//   overlap. Static-static pairs are excluded by the filter masks and joined pairs by an overlap
//   filter: filtered pairs never become pairs. The dispatcher gives every pair of shape types one
//   collision algorithm of ours (PairAlgorithm): the narrow phase, then the pair's manifold
//   (manifold.hpp). Bullet's own convex algorithms and persistent manifolds are not used. Bullet's
//   dispatch only creates the algorithms (serially: its pool is not thread-safe); the pairs then
//   run in parallel, each writing its own manifold, and are read in the pair cache's order, so the
//   contacts do not depend on the thread count.
// - GJK/EPA: btGjkEpaSolver2 on each body's Bullet shape, exact or rounded (the narrow phase's
//   step 1, asked through GjkEpa).
#include "collision/collide.hpp"

#include <btBulletCollisionCommon.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "collision/narrow_phase.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "scene/mass_properties.hpp"

namespace rbpart {

using namespace collision;

namespace {

btVector3 to_bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
Vec3 to_eigen(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

// A body's Bullet shapes: the exact one (margin 0, or a core plus radius) and, for boxes, cylinders
// and hulls, a rounded one (a shrunk core plus `rounding`; none for spheres and capsules).
struct BulletShapes {
  std::unique_ptr<btConvexShape> exact, rounded;
};

// `core` is a hull's rounded core (make_geometry).
BulletShapes make_bullet_shapes(const Shape& shape, const Geometry& g, const std::vector<Polyhedron>& polyhedra,
                                const std::vector<Vec3>& core) {
  BulletShapes s;
  switch (shape.type) {
    case ShapeType::Sphere:
      s.exact = std::make_unique<btSphereShape>(shape.radius);
      break;
    case ShapeType::Capsule:
      s.exact = std::make_unique<btCapsuleShapeZ>(shape.radius, 2 * shape.half_length);
      break;
    case ShapeType::Cylinder: {
      const btVector3 half(shape.radius, shape.radius, shape.half_length);
      s.exact = std::make_unique<btCylinderShapeZ>(half);
      s.rounded = std::make_unique<btCylinderShapeZ>(half);
      break;
    }
    case ShapeType::Box:
      s.exact = std::make_unique<btBoxShape>(to_bt(shape.half_extents));
      s.rounded = std::make_unique<btBoxShape>(to_bt(shape.half_extents));
      break;
    case ShapeType::Convex: {
      auto exact = std::make_unique<btConvexHullShape>();
      auto rounded = std::make_unique<btConvexHullShape>();
      for (const Vec3& v : polyhedra[g.polyhedron].vertices) exact->addPoint(to_bt(v), false);
      for (const Vec3& v : core) rounded->addPoint(to_bt(v), false);
      exact->recalcLocalAabb();
      rounded->recalcLocalAabb();
      s.exact = std::move(exact);
      s.rounded = std::move(rounded);
      break;
    }
  }
  // Boxes and cylinders keep their outer size when the margin changes: their core shrinks.
  if (s.rounded) {
    s.exact->setMargin(0);
    s.rounded->setMargin(g.rounding);
  }
  return s;
}

// The dispatcher keeps the narrow phase for its algorithms, and the pairs of the current call.
class Dispatcher : public btCollisionDispatcher {
 public:
  Dispatcher(btCollisionConfiguration* config, NarrowPhase* narrow)
      : btCollisionDispatcher(config), narrow_(narrow) {
    setNearCallback(&Dispatcher::create_algorithm);
  }
  NarrowPhase& narrow() { return *narrow_; }
  std::vector<btCollisionAlgorithm*>& pairs() { return pairs_; }

 private:
  // Bullet's default near callback up to the algorithm: creates it if the pair has none and lists
  // it, leaving its run to the caller.
  static void create_algorithm(btBroadphasePair& pair, btCollisionDispatcher& base, const btDispatcherInfo&) {
    auto* o0 = static_cast<btCollisionObject*>(pair.m_pProxy0->m_clientObject);
    auto* o1 = static_cast<btCollisionObject*>(pair.m_pProxy1->m_clientObject);
    if (!base.needsCollision(o0, o1)) return;
    if (!pair.m_algorithm) {
      const btCollisionObjectWrapper w0(nullptr, o0->getCollisionShape(), o0, o0->getWorldTransform(), -1, -1);
      const btCollisionObjectWrapper w1(nullptr, o1->getCollisionShape(), o1, o1->getWorldTransform(), -1, -1);
      pair.m_algorithm = base.findAlgorithm(&w0, &w1, nullptr, BT_CONTACT_POINT_ALGORITHMS);
    }
    if (pair.m_algorithm) static_cast<Dispatcher&>(base).pairs_.push_back(pair.m_algorithm);
  }

  NarrowPhase* narrow_;
  std::vector<btCollisionAlgorithm*> pairs_;
};

// The pair algorithm: runs the narrow phase on its pair and keeps the pair's manifold.
class PairAlgorithm : public btCollisionAlgorithm {
 public:
  PairAlgorithm(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* w0,
                const btCollisionObjectWrapper* w1)
      : btCollisionAlgorithm(ci), a_(w0->getCollisionObject()), b_(w1->getCollisionObject()) {}

  void processCollision(const btCollisionObjectWrapper*, const btCollisionObjectWrapper*, const btDispatcherInfo&,
                        btManifoldResult*) override {
    // Pairs run in parallel (Collider::collide): this writes the pair's own axis and manifold.
    NarrowPhase& narrow = static_cast<Dispatcher*>(m_dispatcher)->narrow();
    const int a = body_a(), b = body_b();
    PairPoint pts[kMaxPoints];
    const int count = narrow.pair_contacts(a, b, axis_, pts);
    manifold_.update(narrow.rotation[a], narrow.position[a], narrow.rotation[b], narrow.position[b],
                     narrow.pair_margin(a, b), pts, count);
  }

  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return 1;
  }
  void getAllContactManifolds(btManifoldArray&) override {}

  int body_a() const { return a_->getUserIndex(); }
  int body_b() const { return b_->getUserIndex(); }
  Manifold& manifold() { return manifold_; }

  struct CreateFunc : btCollisionAlgorithmCreateFunc {
    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                   const btCollisionObjectWrapper* w0,
                                                   const btCollisionObjectWrapper* w1) override {
      void* memory = ci.m_dispatcher1->allocateCollisionAlgorithm(sizeof(PairAlgorithm));
      return new (memory) PairAlgorithm(ci, w0, w1);
    }
  };

 private:
  const btCollisionObject* a_;
  const btCollisionObject* b_;
  Manifold manifold_;
  Vec3 axis_ = Vec3::Zero();  // the pair's last normal: warm start and separation test
};

// Broad-phase filter: Bullet's group/mask test (static-static pairs) and the joined pairs.
struct PairFilter : btOverlapFilterCallback {
  std::vector<std::uint64_t> excluded;  // sorted keys of joined pairs without collide_connected

  static std::uint64_t key(int i, int j) {
    return (static_cast<std::uint64_t>(std::min(i, j)) << 32) | static_cast<std::uint32_t>(std::max(i, j));
  }
  bool needBroadphaseCollision(btBroadphaseProxy* p0, btBroadphaseProxy* p1) const override {
    if (!(p0->m_collisionFilterGroup & p1->m_collisionFilterMask) ||
        !(p1->m_collisionFilterGroup & p0->m_collisionFilterMask))
      return false;
    const int i = static_cast<const btCollisionObject*>(p0->m_clientObject)->getUserIndex();
    const int j = static_cast<const btCollisionObject*>(p1->m_clientObject)->getUserIndex();
    return !std::binary_search(excluded.begin(), excluded.end(), key(i, j));
  }
};

}  // namespace

// The Collider's state; it answers the narrow phase's GJK/EPA queries on its Bullet shapes.
struct Collider::Impl final : GjkEpa {
  NarrowPhase narrow;
  std::vector<char> is_static;
  std::vector<BulletShapes> shapes;  // per body
  std::vector<std::unique_ptr<btCollisionObject>> objects;
  std::vector<double> reach;  // per dynamic body: farthest point of the shape from the centre of mass
  std::vector<Vec3> last_position;
  std::vector<Quat> last_orientation;
  std::vector<double> last_sweep;
  bool posed = false;
  PairFilter filter;
  PairAlgorithm::CreateFunc create_pair;
  std::unique_ptr<btDefaultCollisionConfiguration> config;
  std::unique_ptr<Dispatcher> dispatcher;
  std::unique_ptr<btDbvtBroadphase> broadphase;
  std::unique_ptr<btCollisionWorld> world;  // destroyed first: it releases the pairs and their algorithms
  ContactIds ids;

  GjkEpaResult closest_pair(int a, int b, const Vec3& axis) const override;
};

GjkEpaResult Collider::Impl::closest_pair(int a, int b, const Vec3& axis) const {
  const Geometry& ga = narrow.geometry[a];
  const Geometry& gb = narrow.geometry[b];
  const btTransform& ta = objects[a]->getWorldTransform();
  const btTransform& tb = objects[b]->getWorldTransform();
  // One rounded shape per pair keeps touching cores apart: none next to a sphere or capsule (their
  // cores are a point or a segment), else B's, or A's when only A is a polytope (a cylinder's rim
  // stays exact).
  const bool round_pair = !shapes[a].rounded || !shapes[b].rounded;
  const bool round_a = !round_pair && ga.polyhedron >= 0 && gb.polyhedron < 0;
  const bool round_b = !round_pair && !round_a;
  const btConvexShape* sa = (round_a ? shapes[a].rounded : shapes[a].exact).get();
  const btConvexShape* sb = (round_b ? shapes[b].rounded : shapes[b].exact).get();
  const double ra = round_a ? ga.rounding : ga.core_radius, rb = round_b ? gb.rounding : gb.core_radius;
  const double scale = ga.size + gb.size, tolerance = 1e-9 * scale;

  // Each result is checked against the gap between the Bullet shapes' support planes along its
  // normal, a lower bound that equals the distance (or minus the depth) at the solution:
  // btGjkEpaSolver2's GJK can stop short of the minimum (it ends when a support point repeats one
  // of its last four) and then restarts from its normal; EPA can give up on a thin overlap (it then
  // returns its guess as the normal, at depth 0). btGjkEpaSolver2 works in A's frame: the guess is
  // A - B there, the normal comes back in it.
  btVector3 guess = (axis.squaredNorm() > 0 ? to_bt(axis) : ta.getOrigin() - tb.getOrigin()) * ta.getBasis();
  if (guess.length2() == 0) guess.setValue(0, 0, 1);
  auto rounded_support = [](const btConvexShape* shape, const btTransform& t, const btVector3& world_dir) {
    const btVector3 d = world_dir * t.getBasis();
    return t * (shape->localGetSupportingVertexWithoutMargin(d) + d * shape->getMargin());
  };
  auto plane_gap = [&](const btVector3& local_n) {  // separation of the Bullet shapes along n
    const btVector3 nw = ta.getBasis() * local_n;
    return nw.dot(rounded_support(sa, ta, -nw) - rounded_support(sb, tb, nw));
  };
  GjkEpaResult out;
  btGjkEpaSolver2::sResults r;
  for (int attempt = 0; attempt < 4 && !out.converged; ++attempt) {
    if (!btGjkEpaSolver2::Distance(sa, ta, sb, tb, guess, r) || !(r.distance > tolerance)) break;
    const double d = r.distance - ra - rb;
    out.converged = d - plane_gap(r.normal) <= tolerance;
    guess = r.normal * r.distance;
    const Vec3 n = to_eigen(ta.getBasis() * r.normal);
    out.gjk = {to_eigen(r.witnesses[0]) - ra * n, to_eigen(r.witnesses[1]) + rb * n, n, d};
    out.have_gjk = true;
  }
  if (!out.converged) {
    out.epa_valid = btGjkEpaSolver2::Penetration(sa, ta, sb, tb, guess, r, true) &&
                    std::abs(r.distance - plane_gap(r.normal)) <= 1e-6 * scale;
    out.epa = {to_eigen(r.witnesses[0]), to_eigen(r.witnesses[1]), to_eigen(ta.getBasis() * r.normal), r.distance};
  }
  return out;
}

Collider::Collider(const SceneDef& scene, double margin) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  if (!std::isfinite(margin) || margin < 0)
    throw InputError("contact margin must be finite and non-negative (got " + std::to_string(margin) + ")");
  const int n = static_cast<int>(scene.bodies.size());
  NarrowPhase& narrow = m.narrow;
  narrow.contact_margin = margin;
  narrow.geometry.resize(n);
  narrow.rotation.assign(n, Mat3::Identity());
  narrow.position.assign(n, Vec3::Zero());
  narrow.box_lo.assign(n, Vec3::Zero());
  narrow.box_hi.assign(n, Vec3::Zero());
  narrow.sweep.assign(n, 0.0);
  narrow.velocity.assign(n, Vec3::Zero());
  narrow.angular_velocity.assign(n, Vec3::Zero());
  narrow.com_local.assign(n, Vec3::Zero());
  narrow.gjk_epa = &m;

  btDefaultCollisionConstructionInfo info;
  info.m_customCollisionAlgorithmMaxElementSize = static_cast<int>(sizeof(PairAlgorithm));
  // A pool for the pairs of a dense pile (about 20 broad-phase pairs per body); beyond, Bullet
  // allocates. The pair algorithms keep their points themselves (manifold.hpp): no Bullet manifolds.
  info.m_defaultMaxCollisionAlgorithmPoolSize = std::max(4096, 16 * n);
  info.m_defaultMaxPersistentManifoldPoolSize = 1;
  m.config = std::make_unique<btDefaultCollisionConfiguration>(info);
  m.dispatcher = std::make_unique<Dispatcher>(m.config.get(), &narrow);
  for (int t0 : {SPHERE_SHAPE_PROXYTYPE, BOX_SHAPE_PROXYTYPE, CAPSULE_SHAPE_PROXYTYPE, CYLINDER_SHAPE_PROXYTYPE,
                 CONVEX_HULL_SHAPE_PROXYTYPE})
    for (int t1 : {SPHERE_SHAPE_PROXYTYPE, BOX_SHAPE_PROXYTYPE, CAPSULE_SHAPE_PROXYTYPE, CYLINDER_SHAPE_PROXYTYPE,
                   CONVEX_HULL_SHAPE_PROXYTYPE})
      m.dispatcher->registerCollisionCreateFunc(t0, t1, &m.create_pair);
  m.broadphase = std::make_unique<btDbvtBroadphase>();
  m.world = std::make_unique<btCollisionWorld>(m.dispatcher.get(), m.broadphase.get(), m.config.get());

  for (const JointDef& j : scene.joints) {
    if (j.body_a < 0 || j.body_a >= n || j.body_b < -1 || j.body_b >= n)
      throw InputError("joint between bodies " + std::to_string(j.body_a) + " and " + std::to_string(j.body_b) +
                       ": no such body");
    if (!j.collide_connected && j.body_b >= 0) m.filter.excluded.push_back(PairFilter::key(j.body_a, j.body_b));
  }
  std::sort(m.filter.excluded.begin(), m.filter.excluded.end());
  m.world->getPairCache()->setOverlapFilterCallback(&m.filter);

  m.is_static.resize(n);
  m.reach.assign(n, 0.0);
  m.shapes.resize(n);
  std::vector<Vec3> core;
  for (int i = 0; i < n; ++i) {
    const BodyDef& body = scene.bodies[i];
    m.is_static[i] = body.is_static;
    const Geometry& g = narrow.geometry[i];
    try {
      narrow.geometry[i] = make_geometry(body.shape, margin, narrow.polyhedra, core);
      m.shapes[i] = make_bullet_shapes(body.shape, g, narrow.polyhedra, core);
      if (!body.is_static) {
        // The centre of mass that World's velocities refer to (the same function fixes it there).
        const Vec3 com = narrow.com_local[i] = unit_density_properties(body.shape).com;
        if (g.polyhedron >= 0) {
          for (const Vec3& v : narrow.polyhedra[g.polyhedron].vertices) m.reach[i] = std::max(m.reach[i], (v - com).norm());
        } else {  // sphere, capsule, cylinder: g.size is the farthest point from the frame origin
          m.reach[i] = com.norm() + g.size;
        }
      }
    } catch (const InputError& e) {
      throw InputError("body '" + body.name + "': " + e.what());
    }
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(m.shapes[i].exact.get());
    object->setUserIndex(i);
    if (body.is_static) object->setCollisionFlags(object->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
    const int group = body.is_static ? btBroadphaseProxy::StaticFilter : btBroadphaseProxy::DefaultFilter;
    const int mask = body.is_static ? btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter
                                    : btBroadphaseProxy::AllFilter;
    m.world->addCollisionObject(object.get(), group, mask);
    m.objects.push_back(std::move(object));
  }
  m.last_position.assign(n, Vec3::Zero());
  m.last_orientation.assign(n, Quat::Identity());
  m.last_sweep.assign(n, 0.0);
}

Collider::~Collider() = default;

double Collider::reach(int body) const { return impl_->reach[body]; }

void Collider::collide(const std::vector<Vec3>& frame_position, const std::vector<Quat>& frame_orientation,
                       const std::vector<Vec3>& velocity, const std::vector<Vec3>& angular_velocity, double h,
                       std::vector<Contact>& contacts) {
  Impl& m = *impl_;
  NarrowPhase& narrow = m.narrow;
  const int n = static_cast<int>(m.objects.size());
  if (static_cast<int>(frame_position.size()) != n || static_cast<int>(frame_orientation.size()) != n ||
      static_cast<int>(velocity.size()) != n || static_cast<int>(angular_velocity.size()) != n)
    throw std::invalid_argument("collide: expected " + std::to_string(n) + " poses and velocities");
  if (!std::isfinite(h) || h < 0) throw std::invalid_argument("collide: the step must be finite and non-negative");
  narrow.h = h;

  // Sweeps, poses and broad-phase boxes of the bodies that moved or changed speed. Each box grows
  // by half the contact margin and by its body's sweep, so two boxes overlap when their gap is
  // within the pair's margin.
  for (int i = 0; i < n; ++i) {
    const Vec3& x = frame_position[i];
    const Quat& q = frame_orientation[i];
    if (!x.allFinite() || !q.coeffs().allFinite() || q.squaredNorm() == 0)
      throw std::invalid_argument("collide: body " + std::to_string(i) + " has a non-finite pose");
    if (!velocity[i].allFinite() || !angular_velocity[i].allFinite())
      throw std::invalid_argument("collide: body " + std::to_string(i) + " has a non-finite velocity");
    const double sweep =
        m.is_static[i] ? 0.0
                       : std::min(h * (velocity[i].norm() + angular_velocity[i].norm() * m.reach[i]), kMaxSweep);
    narrow.sweep[i] = sweep;
    if (!m.is_static[i]) {
      narrow.velocity[i] = velocity[i];
      narrow.angular_velocity[i] = angular_velocity[i];
    }
    const bool moved = !m.posed || x != m.last_position[i] || q.coeffs() != m.last_orientation[i].coeffs();
    if (!moved && sweep == m.last_sweep[i]) continue;
    m.last_sweep[i] = sweep;
    btCollisionObject& object = *m.objects[i];
    if (moved) {
      m.last_position[i] = x;
      m.last_orientation[i] = q;
      const Mat3 R = q.normalized().toRotationMatrix();
      narrow.rotation[i] = R;
      narrow.position[i] = x;
      const btTransform t(btMatrix3x3(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)),
                          to_bt(x));
      object.setWorldTransform(t);
      btVector3 lo, hi;
      object.getCollisionShape()->getAabb(t, lo, hi);
      narrow.box_lo[i] = to_eigen(lo);
      narrow.box_hi[i] = to_eigen(hi);
    }
    const double grow = 0.5 * narrow.contact_margin + sweep;
    const btVector3 g(grow, grow, grow);
    m.broadphase->setAabb(object.getBroadphaseHandle(), to_bt(narrow.box_lo[i]) - g, to_bt(narrow.box_hi[i]) + g,
                          m.dispatcher.get());
  }
  m.posed = true;

  m.world->computeOverlappingPairs();
  std::vector<btCollisionAlgorithm*>& active = m.dispatcher->pairs();
  active.clear();
  const btDispatcherInfo& info = m.world->getDispatchInfo();
  m.dispatcher->dispatchAllCollisionPairs(m.world->getPairCache(), info, m.dispatcher.get());
  parallel_for_each(active.size(), [&](std::size_t k) { active[k]->processCollision(nullptr, nullptr, info, nullptr); });

  // Contacts with body_a dynamic (the lower index when both are), normal from b into a.
  contacts.clear();
  btBroadphasePairArray& pairs = m.world->getPairCache()->getOverlappingPairArray();
  for (int k = 0; k < pairs.size(); ++k) {
    if (!pairs[k].m_algorithm) continue;
    PairAlgorithm& pair = *static_cast<PairAlgorithm*>(pairs[k].m_algorithm);
    const int i0 = pair.body_a(), i1 = pair.body_b();
    const bool swap = m.is_static[i0] || (!m.is_static[i1] && i1 < i0);
    Manifold& manifold = pair.manifold();
    for (int p = 0; p < manifold.count(); ++p) {
      PairContact& pc = manifold.contact(p);
      Contact c;
      c.body_a = swap ? i1 : i0;
      c.body_b = swap ? i0 : i1;
      c.normal = swap ? Vec3(-pc.point.normal) : pc.point.normal;
      c.point = 0.5 * (pc.point.on_a + pc.point.on_b);
      c.distance = pc.point.distance;
      c.id = m.ids.id(pc);
      contacts.push_back(c);
    }
  }
  m.ids.sort_and_number(contacts);
}

}  // namespace rbpart
