#pragma once
// Spring-mass water parameters (Markichev & Supikov): lattice form and physical form.
//
// Lattice: node mass m (kg), spring stiffness c (N/m), spacing h (m), rest length
// l_rest = rest_ratio * h (< h: pre-tension, so small vertical waves have a restoring
// force), damping gamma (N s/m: force -gamma v on each node).
// Small vertical motion then obeys the wave equation with speed
//   c_w = h * sqrt(3 c (1 - rest_ratio) / m).
// Physical: cell size, water depth (c_w = sqrt(g depth)) or wave speed, density and an
// amplitude damping time; mass, stiffness and gamma follow.

namespace shore::water {

struct LatticeParameters {
  double spacing = 1.0;     ///< h, m, > 0
  double mass = 4.0;        ///< m, kg per node, > 0
  double stiffness = 7.0;   ///< c, N/m per spring, > 0
  double rest_ratio = 0.9;  ///< l_rest / h, in (0, 1]; 1 means no pre-tension (no small waves)
  double damping = 0.05;    ///< gamma, N s/m: force -gamma v per node, >= 0

  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;
  /// c_w = h sqrt(3 c (1 - rest_ratio) / m), m/s.
  [[nodiscard]] double wave_speed() const;
  /// k_t = c (1 - rest_ratio), N/m: the vertical stiffness of every pre-tensioned spring
  /// (axis and diagonal alike: tension over length), the linearised vertical coupling.
  [[nodiscard]] double transverse_stiffness() const;
  /// Amplitude e-folding time 2 m / gamma (s); infinite without damping.
  [[nodiscard]] double damping_time() const;
  /// The seed paper's preset: h 1, m 4, c 7, gamma 0.05 (its dt was 0.4).
  static LatticeParameters paper();
};

struct PhysicalParameters {
  double cell = 0.05;         ///< m, node spacing, > 0
  double depth = 0.5;         ///< m, water depth: sets c_w = sqrt(g depth) and the node mass, > 0
  double wave_speed = 0.0;    ///< m/s, >= 0; 0: c_w = sqrt(g depth), else c_w = wave_speed
  double density = 1000.0;    ///< kg/m^3, > 0
  double damping_time = 5.0;  ///< s, amplitude e-folding time, > 0 (infinity: undamped)
  double rest_ratio = 0.9;    ///< l_rest / h, in (0, 1)
  double gravity = 9.81;      ///< m/s^2, > 0

  void validate() const;
  /// Wave speed c_w: wave_speed if set, else sqrt(g depth), m/s.
  [[nodiscard]] double target_wave_speed() const;
  /// Node mass rho h^2 depth; stiffness c = c_w^2 m / (3 h^2 (1 - rest_ratio)) so that the
  /// lattice's wave speed is c_w; gamma = 2 m / damping_time.
  [[nodiscard]] LatticeParameters to_lattice() const;
};

}  // namespace shore::water
