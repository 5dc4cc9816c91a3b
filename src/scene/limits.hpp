#pragma once
// Bounds on what a scene may ask for, checked wherever a scene comes in (scene files, --set, --dt)
// so that bad input is refused with exit status 2 naming it (issue #26). Beyond them the double
// precision dynamics overflow or underflow (a mass of 1e308, a radius of 1e200, a dt of 1e300 ended
// in an internal error), or the scene outgrows memory before its first step (--set rocks=1e8).
namespace rbpart::limits {

constexpr double kMaxDt = 1;                        // s
constexpr double kMinMass = 1e-9, kMaxMass = 1e12;  // kg, of a dynamic body
constexpr double kMinLength = 1e-6;                 // m: shape sizes, a hull's extent
constexpr double kMaxLength = 1e4;                  // m: shape sizes and vertex coordinates
constexpr int kMaxCount = 10000;                    // bodies one scene parameter may ask for
// Of a scene file's gravity (m/s^2) and a body's starting velocity (m/s) and angular velocity
// (rad/s), per component: at 1e300 the first step's kinetic energy overflowed (an internal error).
constexpr double kMaxRate = 1e6;

}  // namespace rbpart::limits
