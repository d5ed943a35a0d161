// physics may not use case: this must not build.
#include "talus/case/case.hpp"
