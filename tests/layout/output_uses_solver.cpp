// output may use solver: this builds (the check's control).
#include "talus/solver/simulation.hpp"
