// Built with -ffast-math on purpose: the instruction scan must find the reciprocal
// square-root estimate here, or it could not find one in the libraries either.
#include <cmath>

float probe_reciprocal_sqrt(float x) { return 1.0f / std::sqrt(x); }
