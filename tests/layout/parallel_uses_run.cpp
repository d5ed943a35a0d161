// parallel may not use run: this must not build.
#include "talus/run/run.hpp"
