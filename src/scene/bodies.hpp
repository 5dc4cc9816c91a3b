#pragma once
// The bodies of a World, per field, in scene order: constants from the definition, then the state
// that the step advances. Static bodies have inv_mass 0 and a zero inverse inertia.
#include <rbpart/scene.hpp>

#include <vector>

namespace rbpart {

struct Bodies {
  // Constants.
  std::vector<char> is_static;
  std::vector<double> mass;            // kg (0 for static bodies)
  std::vector<double> inv_mass;        // 1/kg (0 for static bodies)
  std::vector<Mat3> inertia_body;      // about the centre of mass, shape-frame axes
  std::vector<Mat3> inv_inertia_body;
  std::vector<Vec3> com_local;         // centre of mass in the shape frame
  std::vector<double> friction;        // Coulomb coefficient per body
  // State: centre of mass, orientation (unit), linear and angular velocity (world).
  std::vector<Vec3> x;
  std::vector<Quat> q;
  std::vector<Vec3> v, w;
  // Rotational geometric stiffness of the joints on each body, h^2 |dtau/dtheta| (kg m^2), from the
  // last step's joint impulses; added to the inertia so stiff chains stay stable (integrate.hpp).
  std::vector<double> geometric_stiffness;
  // Derived each step: world inverse of the (stiffness-augmented) inertia, (R I R^T + k 1)^-1.
  std::vector<Mat3> inv_inertia;

  int size() const { return static_cast<int>(x.size()); }
  Vec3 frame_position(int i) const { return x[i] - q[i] * com_local[i]; }
};

}  // namespace rbpart
