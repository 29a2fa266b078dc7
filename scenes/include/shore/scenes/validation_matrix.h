#pragma once
// The validation matrix: Wong's soils (Theory of Ground Vehicles, table of Bekker and shear
// parameters) crossed with the soil cases of soil_cases.h, each cell measured against its
// outside reference (Bekker's closed forms, Wong and Reece's driven wheel, Coulomb on the
// soil's phi and c, the column model's energy balance) with a tolerance. Run whole by
// shore-bench's "matrix" sweep, sampled by the tests.

#include <cmath>
#include <string>
#include <vector>

#include "shore/scenes/sliding_block.h"
#include "shore/terrain/material.h"

namespace shore::scenes {

/// A soil of the matrix and the loads it is tried at. Loads differ per soil because the
/// soils differ a hundredfold in stiffness: each was chosen (round numbers) so Bekker's
/// sinkage stays within a few centimetres to about D / 6, where the closed forms hold.
struct MatrixSoil {
  std::string name;            ///< "dry sand", "LETE sand", ... (Wong's names)
  terrain::Material material;  ///< the preset if there is one, else sand() with Wong's n, k_c, k_phi, c, phi, K
  double plate_pressure[2];    ///< Pa, on square plates 0.2 m and 0.4 m wide
  double wheel_load[2];        ///< N, rigid wheels D 0.5 m and 0.8 m, b 0.3 m, static and towed
  double driven_load;          ///< N, driven wheel D 0.6 m, b 0.15 m
  double box_mass;             ///< kg, the 0.3 m square, 0.06 m tall box on the slopes: it sinks 5 mm (Bekker)
  bool preset;                 ///< true: a shore::terrain::Material preset
};

/// Wong's soils: dry sand (the sand preset), LETE sand, sandy loam at 15 % and 22 %
/// moisture, clayey soil at 38 % and 55 % (the mud preset), heavy clay at 25 %, snow (the
/// snow preset). K, where Wong gives none, 1 cm.
std::vector<MatrixSoil> matrix_soils();

/// One run of the matrix: a soil and a case family with its settings.
struct MatrixCase {
  std::size_t soil = 0;  ///< index into matrix_soils()
  /// "plate", "wheel static", "wheel towed", "driven wheel", "slope box", "sphere drop"
  std::string family;
  double size = 0.0;   ///< m: plate width, wheel diameter, driven wheel diameter, box side, sphere diameter
  double load = 0.0;   ///< plate: Pa; wheels: N; slope box: kg; sphere: kg
  double slip = 0.0;   ///< driven wheel
  double slope = 0.0;  ///< rad, slope box
  std::string label;   ///< "0.2 m, 20 kPa", "slip 0.2", "phi + 7 deg" ...
  /// Slope box: the cell is the mean over this many starts spread over a column cell
  /// (across and down the slope), an estimate of the continuum slide; 0: one start with the
  /// box's sides on a row of column centres (the matrix before; docs/terrain.md,
  /// "Validation matrix").
  int box_starts = 4;
  double box_shift = 0.0;  ///< m, slope box: every start moved across the slope by this too
};

/// Every run of the matrix (quick: a subset of each family on every soil).
std::vector<MatrixCase> matrix_cases(bool quick);

/// One cell: a quantity measured against its reference.
struct MatrixCell {
  std::string soil, family, label;
  std::string quantity;   ///< "sinkage", "drawbar pull", "torque", "resistance", "acceleration (whole)", ...
  double measured = 0.0;  ///< in the quantity's unit (m, N, N m, m/s^2)
  double reference = 0.0;
  double error = 0.0;      ///< signed, relative to the reference (pull: of the load)
  double tolerance = 0.0;  ///< on |error|
  /// "relative", "of W" or "of g sin(theta)" (a box that should hold or barely slide)
  std::string error_kind;
  /// Empty, or why the reference's own assumptions do not hold for this cell (docs/terrain.md,
  /// "Validation matrix"): such a cell is reported but not counted against the model.
  std::string outside_validity;
  std::string note;           ///< what else the run showed (a box's largest tilt and slide), or empty
  double wall_seconds = 0.0;  ///< of the whole run the cell came from
  [[nodiscard]] bool within() const { return std::abs(error) <= tolerance; }
  [[nodiscard]] double error_over_tolerance() const { return std::abs(error) / tolerance; }
};

/// A slope box case's reference: Wong's sliding block on the soil's Janosi-Hanamoto curve,
/// less the compaction resistance of the box's front edge at Bekker's sinkage (sliding_block.h),
/// and whether its assumptions hold for the case.
struct SlopeBoxReference {
  double drive = 0.0;  ///< m/s^2, g sin(theta)
  SlidingBlockMotion motion;
  /// m: how far ahead of the base's middle the sliding block's normal push must act
  /// (base_eccentricity at its steady share of the strength), and how far Bekker's soil can
  /// move it with the whole base bearing (bearing_eccentricity_limit)
  double eccentricity = 0.0, eccentricity_limit = 0.0;
  /// Empty, or why the block is outside its validity: a box that slides with its base's
  /// eccentricity beyond the limit rides on its front edge and ploughs, where the block
  /// slides on the surface at Bekker's sinkage (docs/terrain.md, "Validation matrix").
  std::string outside_validity;
  /// A block that holds or barely slides over the whole run (below a tenth of the
  /// frictionless g sin(theta)); each cell whose own reference is that small is judged
  /// against g sin(theta).
  [[nodiscard]] bool holds() const { return motion.whole < 0.1 * drive; }
};

/// The reference of a "slope box" case (the box 0.06 m tall, 1.5 s from rest).
SlopeBoxReference slope_box_reference(const MatrixCase& c);

/// Runs one case (one thread, 1 cm cells, 1/240 s) and returns its cells.
std::vector<MatrixCell> run_matrix_case(const MatrixCase& c);

}  // namespace shore::scenes
