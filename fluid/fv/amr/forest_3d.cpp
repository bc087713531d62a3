// The octree forest engine (3D): forest_p4est_impl.hpp renamed to p8est by
// p4est's own p4est_to_p8est.h.
#include <p4est_to_p8est.h>
#include <p8est_bits.h>
#include <p8est_extended.h>
#include <p8est_ghost.h>

#define COFLOW_FOREST_ENGINE make_forest_engine_3d
#include "fluid/fv/amr/forest_p4est_impl.hpp"
