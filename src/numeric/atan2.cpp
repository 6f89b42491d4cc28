// The double tier's atan2, compiled once for the base instruction set: the vectorised kernels call this copy
// (numeric/atan2.hpp).
#include "numeric/atan2.hpp"

namespace rotleak::formula {

double atan2_scalar(double y, double x) { return atan2_of(y, x); }

}  // namespace rotleak::formula
