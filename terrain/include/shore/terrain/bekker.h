#pragma once
// Bekker's pressure-sinkage law and the closed forms built on it (Wong, Theory of Ground
// Vehicles, ch. 2). These are the outside references the tests and benchmarks measure
// the column model against, and the yield law the soil uses.

#include "shore/terrain/material.h"

namespace shore::terrain::bekker {

/// Pressure (Pa) that sinks a plate of smaller width b (m) by z (m): (k_c/b + k_phi) z^n.
double pressure(const Material& m, double b, double z);

/// Quasi-static plate sinkage (m) under pressure p (Pa): z = (p / (k_c/b + k_phi))^(1/n).
double plate_sinkage(const Material& m, double b, double p);

/// Sinkage (m) of a rigid-plastic plate released at rest under pressure p: it overshoots
/// the quasi-static value by (n+1)^(1/n) (work of the weight = plastic work).
double plate_sinkage_released(const Material& m, double b, double p);

/// Rolling rigid wheel, front half bearing: z0 = [3W / ((3-n)(k_c + b k_phi) sqrt(D))]^(2/(2n+1)).
/// W in N, D diameter and b width in m.
double wheel_sinkage_rolling(const Material& m, double W, double D, double b);

/// Rolling rigid wheel, front half bearing, as Bekker sets it up but integrated without the
/// closed form's two approximations: solves W = b \int_0^{x0} (k_c/b + k_phi) z(x)^n dx with
/// z(x) = z0 - (R - sqrt(R^2 - x^2)). The closed form takes the rim as the parabola
/// z0 - x^2/D and \int_0^1 (1 - t^2)^n dt as 1 - n/3 (exact at n 0 and 1 only), so it departs
/// from this by up to +20 % on the clays at z0/D 0.14 and by -9 % on snow (n 1.6) at any
/// depth (docs/terrain.md, "Validation matrix").
double wheel_sinkage_rolling_integral(const Material& m, double W, double D, double b);

/// Rigid wheel pressed statically, both halves bearing: solves
/// W = 2 b \int_0^{x0} (k_c/b + k_phi) z(x)^n dx with z(x) = z0 - (R - sqrt(R^2 - x^2)).
double wheel_sinkage_static(const Material& m, double W, double D, double b);

/// Compaction resistance (N) of a rolling wheel with sinkage z0: (k_c + b k_phi) z0^(n+1)/(n+1).
double wheel_compaction_resistance(const Material& m, double z0, double b);

}  // namespace shore::terrain::bekker
