// case may not use solver: this must not build (tests/layout/check_layout.py).
#include "talus/solver/simulation.hpp"
