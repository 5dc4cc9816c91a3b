// End-of-run measures, one definition for every engine and for rbpart's state files: kinetic
// energy, the fastest surface point, and the deepest penetration as one detector sees it (Bullet's
// double-precision narrow phase on a fresh collision world: exact box-box, GJK/EPA otherwise).
#include <btBulletCollisionCommon.h>

#include <cmath>
#include <set>

#include "peers.hpp"

namespace peers {

EndMeasures measure_state(const Scene& scene, const std::vector<BodyState>& state) {
  EndMeasures out;
  for (size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& b = scene.bodies[i];
    if (b.is_static) continue;
    const BodyState& s = state[i];
    const Vec3 iw = world_inertia_times(rotation(s.orientation), b.inertia, s.angular_velocity);
    out.kinetic_energy += 0.5 * b.mass * dot(s.velocity, s.velocity) + 0.5 * dot(s.angular_velocity, iw);
    const double speed = std::sqrt(dot(s.velocity, s.velocity)) +
                         std::sqrt(dot(s.angular_velocity, s.angular_velocity)) * bounding_radius(b.shape);
    out.max_point_speed = std::max(out.max_point_speed, speed);
  }
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btCollisionWorld world(&dispatcher, &broadphase, &config);
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btCollisionObject>> objects;
  for (size_t i = 0; i < scene.bodies.size(); ++i) {
    const Shape& s = scene.bodies[i].shape;
    switch (s.type) {
      case ShapeType::box:
        shapes.push_back(std::make_unique<btBoxShape>(btVector3(s.half_extents[0], s.half_extents[1], s.half_extents[2])));
        break;
      case ShapeType::sphere: shapes.push_back(std::make_unique<btSphereShape>(s.radius)); break;
      case ShapeType::capsule: shapes.push_back(std::make_unique<btCapsuleShapeZ>(s.radius, 2 * s.half_length)); break;
    }
    auto object = std::make_unique<btCollisionObject>();
    const auto& q = state[i].orientation;
    const auto& p = state[i].position;
    object->setWorldTransform(btTransform(btQuaternion(q[1], q[2], q[3], q[0]), btVector3(p[0], p[1], p[2])));
    object->setCollisionShape(shapes.back().get());
    object->setUserIndex(static_cast<int>(i));
    world.addCollisionObject(object.get());
    objects.push_back(std::move(object));
  }
  std::set<std::pair<int, int>> joined;
  for (const auto& j : scene.joints)
    if (j.b >= 0) joined.insert({std::min(j.a, j.b), std::max(j.a, j.b)});
  world.performDiscreteCollisionDetection();
  out.penetration = 0;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    const int a = manifold->getBody0()->getUserIndex(), b = manifold->getBody1()->getUserIndex();
    if (scene.bodies[a].is_static && scene.bodies[b].is_static) continue;
    if (joined.count({std::min(a, b), std::max(a, b)})) continue;
    for (int k = 0; k < manifold->getNumContacts(); ++k)
      out.penetration = std::max(out.penetration, -double(manifold->getContactPoint(k).getDistance()));
  }
  for (auto& o : objects) world.removeCollisionObject(o.get());
  return out;
}

}  // namespace peers
