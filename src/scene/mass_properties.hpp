#pragma once
// Exact mass, centre of mass and inertia of each shape (a convex hull by its tetrahedra).
#include <rbpart/scene.hpp>

namespace rbpart {

struct MassProperties {
  double volume = 0;            // m^3
  double mass = 0;              // kg
  Vec3 com = Vec3::Zero();      // centre of mass in the shape frame
  Mat3 inertia = Mat3::Zero();  // about the centre of mass, in shape-frame axes (kg m^2)
};

// Volume, centre of mass and inertia of the shape at unit density.
MassProperties unit_density_properties(const Shape& shape);

// The body's properties from its shape and its mass (or density when mass is 0).
// Throws InputError if the shape is degenerate (zero volume, non-positive sizes, < 4 hull points).
MassProperties mass_properties(const BodyDef& body);

}  // namespace rbpart
