// output may not use parallel: this must not build.
#include "talus/parallel/processes.hpp"
