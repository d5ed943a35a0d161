// core may not use physics: this must not build.
#include "talus/physics/band.hpp"
