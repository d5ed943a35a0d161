// setup may use case: this builds (the check's control).
#include "talus/case/geometry.hpp"
