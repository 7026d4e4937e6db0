// devices/falcon/falcon_kinematics.hpp - the Falcon's delta kinematics in SI units: encoder counts to joint
// angles, inverse kinematics in closed form, forward kinematics by Newton iteration, the joint Jacobian, force to
// motor torque through its transpose, and torque to motor command units.
//
// Geometry, encoder scaling and sign conventions are those libnifalcon publishes (include/falcon/core/FalconGeometry.h,
// FalconKinematic.h::getTheta, src/kinematic/FalconKinematicStamper.cpp), after R. E. Stamper's parallel-manipulator
// analysis (PhD thesis, University of Maryland, 1997). Read for facts; the equations below are derived here.
//
// Frame (libnifalcon's, metres): origin on the axis of the three legs at the device's base, x to the user's
// right, y up, z out of the device toward the user; the grip rests near z = 0.115 m.
//
// Each leg i sits at angle phi_i about z; in the leg's own frame (u, v, w) = R(phi_i) p + (-r, -s, 0) the loop
// closure of thigh (length a, joint angle theta1, the motor), parallelogram shin (length b, angle theta3) and the
// knee/ankle offsets d, e, c, f is
//     u = a cos(theta1) - c + L cos(theta2),   v = b cos(theta3) - f,   w = a sin(theta1) + L sin(theta2),
// with L = d + e + b sin(theta3). Differentiating and eliminating theta2 and theta3 gives the Jacobian row
//     d theta1 / d(u, v, w) = (cos(theta2) sin(theta3), cos(theta3), sin(theta2) sin(theta3)) / (a sin(theta3) sin(theta2 - theta1)).
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "core/math.hpp"

namespace tridex::devices::falcon {

/// The Falcon's mechanical constants, metres and radians: libnifalcon's current include/falcon/core/FalconGeometry.h
/// (libnifalcon/libnifalcon at f7c727a; r and s as corrected in its commit 935a31e, c = 0.01443).
struct FalconGeometry {
    double a = 0.060;     ///< thigh: leg base to knee, m
    double b = 0.1025;    ///< shin parallelogram side, m
    double c = 0.01443;   ///< shin joint to end-effector centre, u component, m
    double d = 0.01125;   ///< shin to end-effector joint, m
    double e = 0.01125;   ///< knee to shin joint, m
    double f = -0.025;    ///< shin joint to end-effector centre, v component, m
    double r = 0.0400;    ///< frame origin to leg base, u component, m
    double s = -0.02309;  ///< frame origin to leg base, v component, m
    /// Leg angles about z: 90, -30 and -150 degrees, each plus the 15 degree tilt of the axes from the desk.
    std::array<double, 3> phi{glm::radians(90.0 + 15.0), glm::radians(-30.0 + 15.0), glm::radians(-150.0 + 15.0)};
    /// Encoder: 320 slots, x4 quadrature = 1280 counts per motor turn; capstan 14.25 mm driving a 110 mm arm
    /// drum: 2 pi * 0.01425 / (1280 * 0.110) = 6.359e-4 rad per count (about 64 um at the grip: Novint's 400 dpi).
    double rad_per_count = 2.0 * 3.14159265358979323846 * 0.01425 / (1280.0 * 0.110);
    /// theta1 at encoder count 0 (35 degrees).
    double theta_offset_rad = glm::radians(35.0);
};

/// The three joint angles of one leg, rad.
struct LegAngles {
    double theta1 = 0.0;  ///< thigh (motor) angle
    double theta2 = 0.0;  ///< knee angle
    double theta3 = 0.0;  ///< shin (parallelogram) angle
};
using FalconAngles = std::array<LegAngles, 3>;

/// The joint Jacobian G = d theta1 / d p (rows = legs, device frame), rad/m; stored as its three rows.
using JointJacobian = std::array<Vec3, 3>;

/// Kinematics of one Falcon (stateless apart from its geometry; every function is thread-compatible).
class FalconKinematics {
public:
    explicit FalconKinematics(FalconGeometry g = {}) : g_(g) {}
    const FalconGeometry& geometry() const { return g_; }

    /// Motor angle theta1 (rad) of an encoder count: offset + count * rad_per_count.
    double encoder_to_theta(std::int32_t count) const { return g_.theta_offset_rad + count * g_.rad_per_count; }
    /// The nearest encoder count of a motor angle (the quantisation a real encoder applies), saturated to int16.
    std::int16_t theta_to_encoder(double theta_rad) const;

    /// Joint angles of the grip at p (m, device frame); nullopt when p is out of reach (a leg cannot close).
    std::optional<FalconAngles> inverse(const Vec3& p) const;
    /// G = d theta1 / d p at the angles of inverse(p) (rad/m).
    JointJacobian jacobian(const FalconAngles& angles) const;

    /// Result of forward kinematics.
    struct Forward {
        Vec3 position{0.0};         ///< m
        int iterations = 0;         ///< Newton steps taken
        double residual_rad = 0.0;  ///< max |theta1(p) - theta1 wanted| at the end
        bool converged = false;
    };
    /// The grip position whose motor angles are theta1 (rad), by damped Newton iteration on inverse() with
    /// jacobian() from `guess` (the previous position; the home pose when unknown): converged when every motor
    /// angle is within tol_rad (1e-12 rad is about 1e-13 m here). Typically 2-4 steps from the previous tick's position.
    Forward forward(const Vec3& theta1, const Vec3& guess, double tol_rad = 1e-12, int max_iterations = 30) const;

    /// Motor torques (N*m) that make the grip push with force F (N) at p: tau = J^T F with J = dp/dtheta = G^-1.
    /// nullopt when p is out of reach or the Jacobian is singular.
    std::optional<Vec3> force_to_torque(const Vec3& p, const Vec3& force_n) const;
    /// The force (N) motor torques produce at p: F = G^T tau (the emulator's side).
    std::optional<Vec3> torque_to_force(const Vec3& p, const Vec3& torque_nm) const;

    /// The grip's rest position, device frame (the centre of the profile's workspace), m.
    static Vec3 home_m() { return Vec3(0.0, 0.0, 0.115); }

private:
    FalconGeometry g_;
};

/// Motor command scaling (libnifalcon FalconKinematicStamper::getForces): command = -10000 * torque (N*m), one
/// scale for all motors, so that a torque that would overflow is cut in proportion on every motor (the force keeps
/// its direction).
inline constexpr double kCommandPerNm = 10000.0;
/// Largest motor command the driver sends (the 16-bit field's range).
inline constexpr std::int16_t kMaxMotorCommand = 32767;
/// Motor commands for torques tau (N*m): -kCommandPerNm * tau, all three scaled down together when one would
/// exceed max_command; non-finite torques give zero. `clamped` (may be null) says whether they were scaled.
std::array<std::int16_t, 3> torque_to_command(const Vec3& torque_nm, std::int16_t max_command = kMaxMotorCommand,
                                              bool* clamped = nullptr);
/// The torques (N*m) motor commands stand for (the inverse of torque_to_command within one count).
Vec3 command_to_torque(const std::array<std::int16_t, 3>& command);

}  // namespace tridex::devices::falcon
