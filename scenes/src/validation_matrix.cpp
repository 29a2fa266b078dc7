#include "shore/scenes/validation_matrix.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include "shore/scenes/sliding_block.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/wong_reece.h"
#include "shore/terrain/bekker.h"

namespace shore::scenes {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kGravity = 9.81;

/// Sand's appearance, spray and unloading with Wong's bearing and shear parameters (k_c in
/// kN/m^(n+1), k_phi in kN/m^(n+2), c in kPa, phi in degrees, K in m): what a user picking
/// a soil from the table gets.
terrain::Material wong_soil(const std::string& name, double n, double kc, double kphi, double c, double phi, double K) {
  terrain::Material m = terrain::Material::sand();
  m.name = name;
  m.bekker_n = n;
  m.bekker_kc = kc * 1e3;
  m.bekker_kphi = kphi * 1e3;
  m.cohesion = c * 1e3;
  m.friction_angle = phi * kDeg;
  m.shear_modulus = K;
  return m;
}

/// `m` without an unloading branch, as the clay preset (mud) has. Sand's A_u on a soil whose
/// Bekker pressure at a few cm is fifty times sand's puts every relieved column at the
/// floor p / z (A_u z^2 < p), where it springs back its whole sinkage: heavy clay's driven
/// wheel then rode on a rear arc as long as its front one (docs/terrain.md, "Validation
/// matrix"). Clay's compaction is plastic; Wong's table gives no A_u for it.
terrain::Material rigid_plastic(terrain::Material m) {
  m.unload_modulus = 0.0;
  return m;
}

/// A number as %g prints it: "0.2", "20", "1.5".
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

double rel(double measured, double reference) { return (measured - reference) / reference; }

MatrixCell cell(const MatrixCase& c, const MatrixSoil& s, std::string quantity, double measured, double reference,
                double error, double tolerance, std::string kind) {
  MatrixCell out;
  out.soil = s.name;
  out.family = c.family;
  out.label = c.label;
  out.quantity = std::move(quantity);
  out.measured = measured;
  out.reference = reference;
  out.error = error;
  out.tolerance = tolerance;
  out.error_kind = std::move(kind);
  return out;
}

SoilRun one_thread(const terrain::Material& m) {
  SoilRun r;  // one thread already
  r.terrain.material = m;
  return r;
}

std::vector<MatrixCell> plate_cells(const MatrixCase& c, const MatrixSoil& s) {
  PlateCase p;
  p.run = one_thread(s.material);
  p.width = c.size;
  p.pressure = c.load;
  p.ramp_seconds = 3.0;  // quasi-static: Bekker's plate law, not the released overshoot
  p.ease = true;         // arriving at rest (a linear ramp overshoots on rigid-plastic soil)
  p.settle_seconds = 0.5;
  const PlateResult r = run_plate(p);
  return {cell(c, s, "sinkage", r.sinkage, r.reference, rel(r.sinkage, r.reference), 0.03, "relative")};
}

/// Bekker's rolling wheel as he sets it up: his pressure over the circular front arc
/// carrying the load, solved exactly (the integral), as the static wheel's cells already are
/// over the whole arc. His published closed form takes the rim as a parabola and (1 - t^2)^n
/// as 1 - n t^2, which departs from that integral by -16 % to +11 % in sinkage (small z0 / D,
/// n far from 1: docs/terrain.md, "Validation matrix"); the note keeps it.
void note_closed_form(MatrixCell& m, double closed, double integral) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "Bekker's closed form %.5g (%+.1f %% of the integral), measured %+.1f %% of it",
                closed, 100.0 * rel(closed, integral), 100.0 * rel(m.measured, closed));
  m.note = buf;
}

/// The towed wheel's sinkage is judged against Bekker's rolling wheel with the rim's shear:
/// Bekker's pressure over the circular front arc, as his wheel is, and Janosi and
/// Hanamoto's shear along the rim's slip on the soil (Wong and Reece), at the skid where
/// the torque on the free wheel vanishes. Bekker leaves the shear out; a towed wheel's
/// shear ahead of the bottom and behind it balance in torque, but still carry part of the
/// load (tau sin(theta)), by the soil's strength, and the model's rim carries its shear as
/// the soil does. On soil without strength it is Bekker's integral; on these soils it is
/// 0.1 % to 9 % shallower (the heavy, strong cases most). The note keeps Bekker's integral.
double towed_sinkage_with_shear(const terrain::Material& soil, const WheelCase& w, double& skid) {
  WongReeceWheel ref;
  ref.radius = w.diameter / 2, ref.width = w.width, ref.load = w.load, ref.soil = soil;
  ref.front_only = true;
  const TowedWongReeceResult t = wong_reece_towed(ref);
  skid = t.slip;
  return t.wheel.sinkage;
}

void note_bekker_integral(MatrixCell& m, double integral, double skid) {
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "; Wong-Reece towed at skid %.3f; Bekker's integral without shear %.5g (measured %+.1f %% of it)", skid,
                integral, 100.0 * rel(m.measured, integral));
  m.note += buf;
}

std::vector<MatrixCell> wheel_cells(const MatrixCase& c, const MatrixSoil& s, bool towed) {
  WheelCase w;
  w.run = one_thread(s.material);
  w.diameter = c.size;
  w.width = 0.3;
  w.load = c.load;
  w.towed = towed;
  const WheelResult r = run_wheel(w);
  if (!towed)
    return {cell(c, s, "static sinkage", r.sinkage, r.reference_sinkage, rel(r.sinkage, r.reference_sinkage), 0.10,
                 "relative")};
  const double z = terrain::bekker::wheel_sinkage_rolling_integral(s.material, w.load, w.diameter, w.width);
  const double rc = terrain::bekker::wheel_compaction_resistance(s.material, z, w.width);
  double skid = 0.0;
  const double zs = towed_sinkage_with_shear(s.material, w, skid);
  std::vector<MatrixCell> out{cell(c, s, "rolling sinkage", r.sinkage, zs, rel(r.sinkage, zs), 0.10, "relative"),
                              cell(c, s, "resistance", r.resistance, rc, rel(r.resistance, rc), 0.15, "relative")};
  note_closed_form(out[0], r.reference_sinkage, z);
  note_closed_form(out[1], r.reference_resistance, rc);
  note_bekker_integral(out[0], z, skid);
  return out;
}

/// Each driven cell's note keeps Wong and Reece's wheel with Bekker's pressure over the
/// front arc, peaking at the bottom (`front_only`: the stress the towed cells are judged
/// against), beside their own, whose peak lies (0.43 + 0.32 i) theta_1 ahead of it (their
/// coefficients for sand). The two part at zero slip, and the model lies between them: on
/// snow, whose torque is mostly cohesion over the contact arc, that split alone moves the
/// reference torque by 13 % to 16 % (docs/terrain.md, "Validation matrix").
void note_front_arc(MatrixCell& m, double front_arc) {
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "Wong-Reece with Bekker's front arc %.5g (%+.1f %% of theirs), measured %+.1f %% of it", front_arc,
                100.0 * rel(front_arc, m.reference), 100.0 * rel(m.measured, front_arc));
  m.note = buf;
}

/// The same for the drawbar pull, in loads W as its cell.
void note_front_arc_pull(MatrixCell& m, double front_arc, double load) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "Wong-Reece with Bekker's front arc %.5g (%+.3f W of theirs), measured %+.3f W of it",
                front_arc, (front_arc - m.reference) / load, (m.measured - front_arc) / load);
  m.note = buf;
}

std::vector<MatrixCell> driven_cells(const MatrixCase& c, const MatrixSoil& s) {
  DrivenWheelCase d;
  d.run = one_thread(s.material);
  d.diameter = c.size;
  d.width = 0.15;
  d.load = c.load;
  d.slip = c.slip;
  const DrivenWheelResult r = run_driven_wheel(d);
  WongReeceWheel ref;
  ref.radius = c.size / 2, ref.width = d.width, ref.load = d.load, ref.soil = s.material;
  const WongReeceResult want = wong_reece(ref, c.slip);
  ref.front_only = true;
  const WongReeceResult front = wong_reece(ref, c.slip);
  std::vector<MatrixCell> out{
      cell(c, s, "drawbar pull", r.drawbar_pull, want.drawbar_pull, (r.drawbar_pull - want.drawbar_pull) / d.load, 0.08,
           "of W"),
      cell(c, s, "torque", r.torque, want.torque, rel(r.torque, want.torque), 0.15, "relative"),
      cell(c, s, "driven sinkage", r.sinkage, want.sinkage, rel(r.sinkage, want.sinkage), 0.20, "relative")};
  note_front_arc_pull(out[0], front.drawbar_pull, d.load);
  note_front_arc(out[1], front.torque);
  note_front_arc(out[2], front.sinkage);
  return out;
}

constexpr double kBoxHeight = 0.06, kBoxSeconds = 1.5;

std::vector<MatrixCell> slope_cells(const MatrixCase& c, const MatrixSoil& s) {
  SlopeBoxCase b;
  b.run = one_thread(s.material);
  b.slope = c.slope;
  b.size = c.size;
  // A flat box (a sled, 0.06 m tall): Coulomb's block has no moment balance, and a cube's
  // base shear, (c A + N tan(phi)) half its height below the centre of mass, pitches it
  // onto its front edge until it trips (docs/terrain.md, "Validation matrix").
  b.height = kBoxHeight;
  b.mass = c.load;
  b.seconds = kBoxSeconds;
  // The slide is chaotic: starts a micron apart part by 3 % to 7 % in the second half (and
  // more where the box ploughs), and the box's sides on a row of column centres leave edge
  // rows to rounding. The reference is a continuum block, so the cell is the mean over
  // starts spread evenly over a cell across the slope (and, shuffled, down it), none on the
  // tie (docs/terrain.md, "Validation matrix").
  SlopeBoxResult r;
  double lo = 0.0, hi = 0.0;
  const int starts = std::max(c.box_starts, 1);
  for (int k = 0; k < starts; ++k) {
    const double u = (k + 0.5) / starts, cell_size = b.run.terrain.cell;
    b.offset_across = (c.box_starts > 0 ? u * cell_size : 0.0) + c.box_shift;
    b.offset_down = c.box_starts > 0 ? std::fmod(u + 0.5, 1.0) * cell_size : 0.0;
    const SlopeBoxResult one = run_slope_box(b);
    r.acceleration += one.acceleration / starts;
    r.distance += one.distance / starts;
    r.max_tilt = std::max(r.max_tilt, one.max_tilt);
    lo = k == 0 ? one.acceleration : std::min(lo, one.acceleration);
    hi = k == 0 ? one.acceleration : std::max(hi, one.acceleration);
  }
  const SlopeBoxReference want = slope_box_reference(c);
  const double whole = 2.0 * r.distance / (b.seconds * b.seconds);
  // A box that should slide is measured relative to the reference; one that should hold (or
  // barely slide, below a tenth of the frictionless g sin(theta)), against g sin(theta).
  auto judged = [&](const char* quantity, double measured, double reference) {
    const bool holds = reference < 0.1 * want.drive;
    MatrixCell m = cell(c, s, quantity, measured, reference, (measured - reference) / (holds ? want.drive : reference),
                        0.10, holds ? "of g sin(theta)" : "relative");
    m.outside_validity = want.outside_validity;
    return m;
  };
  std::vector<MatrixCell> out = {judged("acceleration, whole slide", whole, want.motion.whole),
                                 judged("acceleration, second half", r.acceleration, want.motion.second_half)};
  for (MatrixCell& each : out)
    each.note = "tilt up to " + num(std::round(r.max_tilt / kDeg)) + " deg, slid " +
                num(std::round(r.distance * 100) / 100) + " m, " + num(std::round(b.mass)) + " kg, second half over " +
                num(starts) + " starts " + num(lo) + " to " + num(hi);
  return out;
}

/// The sphere is judged against the energy balance with the soil's shear on its surface
/// (sphere_drop_reference_depth_with_shear): the model's contact shears the soil along the
/// sphere's tilted surface as it does along a wheel's rim, by the slide against soil at rest
/// that Wong and Reece's rim takes, and past the equator the surface is steep, so its shear
/// (tau tan(beta) per plan area) is of the order of the pressure itself on a soil of large
/// phi. Bekker's plate law has no such surface; the note keeps the plain balance and the
/// share of the model's work on the soil that its shear did.
std::vector<MatrixCell> sphere_cells(const MatrixCase& c, const MatrixSoil& s) {
  SphereDropCase d;
  d.run = one_thread(s.material);
  d.diameter = c.size;
  d.mass = c.load;
  d.height = 1.0;
  const SphereDropResult r = run_sphere_drop(d);
  const double reference = sphere_drop_reference_depth_with_shear(s.material, d.diameter, d.mass, d.height);
  MatrixCell out = cell(c, s, "deepest point", r.max_depth, reference, rel(r.max_depth, reference), 0.10, "relative");
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "energy balance without the surface's shear %.5g (measured %+.1f %% of it); shear %.1f %% of the "
                "work on the soil",
                r.reference, 100.0 * rel(r.max_depth, r.reference),
                100.0 * r.stats.shear_work / std::max(r.stats.soil_work, 1e-12));
  out.note = buf;
  // The energy balance takes the crater as the sphere pressed into columns of its width;
  // once the sphere's top is below the surface the crater's walls close over it, which
  // neither the balance nor Bekker's plate law describes.
  if (reference > c.size) out.outside_validity = "buried (reference depth beyond its diameter)";
  return {out};
}

}  // namespace

std::vector<MatrixSoil> matrix_soils() {
  using terrain::Material;
  // Wong, Theory of Ground Vehicles, table of terrain values: n, k_c, k_phi, c, phi. K from
  // Wong where given (LETE sand 1.2 cm; the presets' own), else 1 cm.
  std::vector<MatrixSoil> soils = {
      {"dry sand", Material::sand(), {20e3, 60e3}, {800, 2000}, 1000, 0.0, true},
      {"LETE sand",
       wong_soil("LETE sand", 0.79, 102, 5301, 1.3, 31.1, 0.012),
       {250e3, 500e3},
       {10e3, 25e3},
       10e3,
       0.0,
       false},
      {"sandy loam 15 %",
       wong_soil("sandy loam 15 %", 0.7, 5.27, 1515.04, 1.72, 29, 0.01),
       {100e3, 200e3},
       {4000, 8000},
       4000,
       0.0,
       false},
      {"sandy loam 22 %",
       wong_soil("sandy loam 22 %", 0.2, 2.56, 43.12, 1.38, 38, 0.01),
       {25e3, 30e3},
       {1000, 1500},
       800,
       0.0,
       false},
      {"clayey soil 38 %",
       wong_soil("clayey soil 38 %", 0.5, 13.19, 692.15, 4.14, 13, 0.01),
       {100e3, 200e3},
       {4000, 8000},
       4000,
       0.0,
       false},
      {"clayey soil 55 % (mud)", Material::mud(), {80e3, 150e3}, {3000, 8000}, 3000, 0.0, true},
      {"heavy clay 25 %",
       rigid_plastic(wong_soil("heavy clay 25 %", 0.13, 12.70, 1555.95, 68.95, 34, 0.01)),
       {900e3, 1100e3},
       {40e3, 60e3},
       30e3,
       0.0,
       false},
      {"snow", Material::snow(), {2000, 5000}, {50, 150}, 100, 0.0, true},
  };
  // The box on the slopes presses the soil 5 mm (Bekker), so it slides on the soil rather
  // than ploughing it: Coulomb's reference assumes a surface, and a box sunk a few cm
  // trips on its front edge (docs/terrain.md, "Validation matrix").
  for (MatrixSoil& s : soils) s.box_mass = terrain::bekker::pressure(s.material, 0.3, 0.005) * 0.3 * 0.3 / kGravity;
  return soils;
}

std::vector<MatrixCase> matrix_cases(bool quick) {
  std::vector<MatrixCase> out;
  const std::vector<MatrixSoil> soils = matrix_soils();
  for (std::size_t k = 0; k < soils.size(); ++k) {
    const MatrixSoil& s = soils[k];
    for (const double width : {0.2, 0.4})
      for (int p = 0; p < 2; ++p)
        if (!quick || (width == 0.2 && p == 1))
          out.push_back({k, "plate", width, s.plate_pressure[p], 0, 0,
                         num(width) + " m, " + num(s.plate_pressure[p] / 1e3) + " kPa"});
    for (const char* family : {"wheel static", "wheel towed"})
      for (const double diameter : {0.5, 0.8})
        for (int w = 0; w < 2; ++w)
          if (!quick || (diameter == 0.8 && w == 1))
            out.push_back({k, family, diameter, s.wheel_load[w], 0, 0,
                           "D " + num(diameter) + " m, " + num(s.wheel_load[w] / 1e3) + " kN"});
    for (const double slip : {0.1, 0.2, 0.3, 0.5})
      if (!quick || slip == 0.1 || slip == 0.5)
        out.push_back({k, "driven wheel", 0.6, s.driven_load, slip, 0,
                       "slip " + num(slip) + ", " + num(s.driven_load / 1e3) + " kN"});
    const double phi = s.material.friction_angle / kDeg;
    for (const double offset : {-7.0, 7.0, 12.0})
      if (!quick || offset == 7.0)
        out.push_back(
            {k, "slope box", 0.3, s.box_mass, 0, (phi + offset) * kDeg,
             (offset < 0 ? "phi - " : "phi + ") + num(std::abs(offset)) + " deg (" + num(phi + offset) + " deg)"});
    out.push_back({k, "sphere drop", 0.2, 10.0, 0, 0, "D 0.2 m, 10 kg, 1 m"});
  }
  return out;
}

namespace {
/// The case's soil; throws std::invalid_argument naming MatrixCase.soil past the table.
MatrixSoil soil_of(const MatrixCase& c) {
  std::vector<MatrixSoil> soils = matrix_soils();
  if (c.soil >= soils.size())
    throw std::invalid_argument("MatrixCase.soil: " + std::to_string(c.soil) + " is not allowed: must be below " +
                                std::to_string(soils.size()));
  return soils[c.soil];
}
}  // namespace

SlopeBoxReference slope_box_reference(const MatrixCase& c) {
  // Coulomb with cohesion, plus the compaction resistance of the box's front edge sinking
  // into fresh soil (Bekker's, for a sledge of width b at sinkage z: b k z^(n+1) / (n+1)),
  // on the soil's Janosi-Hanamoto curve: the base carries c A + m g cos(theta) tan(phi) only
  // where the box has sheared the soil by a few K, none of it at rest and 1 - (K / L)
  // (1 - exp(-L / K)) of it once it has slid its length (Wong's track at full slip,
  // sliding_block.h): m a = m g sin(theta) - R_c - (c A + m g cos(theta) tan(phi)) share(s).
  // With K 0 it is Coulomb's block.
  const terrain::Material m = soil_of(c).material;
  SlopeBoxReference out;
  out.drive = kGravity * std::sin(c.slope);
  const double area = c.size * c.size, normal = kGravity * std::cos(c.slope);
  const double z = terrain::bekker::plate_sinkage(m, c.size, c.load * normal / area);
  const double compaction = terrain::bekker::wheel_compaction_resistance(m, z, c.size);
  SlidingBlock block;
  block.drive = out.drive - compaction / c.load;
  block.strength = normal * std::tan(m.friction_angle) + m.cohesion * area / c.load;
  block.length = c.size;
  block.shear_modulus = m.shear_modulus;
  block.seconds = kBoxSeconds;
  out.motion = slide(block);
  // The block slides on the surface at Bekker's sinkage with its whole base bearing. Its
  // base shear acts half the box's height below the centre of mass, so the soil must push
  // ahead of the middle; where Bekker's pressure grows too little with depth (small n) the
  // base cannot do that by tilting within its sinkage, its rear lifts, and the sliding box
  // rides on its front edge, pressing each fresh column to a few times the level sinkage:
  // it ploughs and descends along its pitch, which the block leaves out. A box that holds
  // meets no fresh soil.
  const double steady = mobilised_share(c.size, c.size, m.shear_modulus);
  out.eccentricity = base_eccentricity(block.strength * steady / normal, kBoxHeight);
  out.eccentricity_limit = bearing_eccentricity_limit(m.bekker_n, c.size);
  if (!out.holds() && out.eccentricity > out.eccentricity_limit)
    out.outside_validity = "the base shear's couple lifts the rear (eccentricity " +
                           num(std::round(out.eccentricity * 1e4) / 10) + " mm, Bekker's n " + num(m.bekker_n) +
                           " bears at most " + num(std::round(out.eccentricity_limit * 1e4) / 10) +
                           " mm): the box rides on its front edge and ploughs";
  return out;
}

std::vector<MatrixCell> run_matrix_case(const MatrixCase& c) {
  const MatrixSoil s = soil_of(c);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<MatrixCell> cells;
  if (c.family == "plate")
    cells = plate_cells(c, s);
  else if (c.family == "wheel static" || c.family == "wheel towed")
    cells = wheel_cells(c, s, c.family == "wheel towed");
  else if (c.family == "driven wheel")
    cells = driven_cells(c, s);
  else if (c.family == "slope box")
    cells = slope_cells(c, s);
  else if (c.family == "sphere drop")
    cells = sphere_cells(c, s);
  else
    throw std::invalid_argument("MatrixCase.family: '" + c.family +
                                "' is not allowed: must be plate, wheel static, wheel towed, driven wheel, slope box "
                                "or sphere drop");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (MatrixCell& m : cells) m.wall_seconds = seconds;
  return cells;
}

}  // namespace shore::scenes
