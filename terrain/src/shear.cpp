#include "shore/terrain/shear.h"

#include <cmath>

#include "shore/core/det_math.h"

namespace shore::terrain::shear {

double strength(const Material& m, double sigma) { return m.cohesion + sigma * det::tan(m.friction_angle); }

double mobilisation(const Material& m, double j) { return 1.0 - det::exp(-std::fabs(j) / m.shear_modulus); }

double stress(const Material& m, double sigma, double j) { return strength(m, sigma) * mobilisation(m, j); }

double loosening(const Material& m, double j) {
  return 1.0 - m.remould_ratio * (1.0 - det::exp(-std::fabs(j) / m.remould_length));
}

double remoulding(const Material& m, double j) { return det::pow(loosening(m, j), m.bekker_n); }

double strength_remoulding(const Material& m, double j) {
  return 1.0 - m.remould_shear_ratio * (1.0 - det::exp(-std::fabs(j) / m.remould_length));
}

}  // namespace shore::terrain::shear
