// The quadtree forest engine (2D): forest_p4est_impl.hpp with p4est's names.
#include <p4est_bits.h>
#include <p4est_extended.h>
#include <p4est_ghost.h>

#define COFLOW_FOREST_ENGINE make_forest_engine_2d
#include "fluid/fv/amr/forest_p4est_impl.hpp"
