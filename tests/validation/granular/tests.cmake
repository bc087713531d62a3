# Granular contacts (dem, dem-reference): two-sphere impact and restitution,
# pouring, bonds and crushing, mesh walls and outlets, crosschecks and ranks.
# Included from tests/CMakeLists.txt (validation/tests.cmake): test names,
# working folders and ${vcfg} are those of tests/.
coflow_validation(dem_two_sphere_impact impact dem_two_sphere_impact.yaml 1)
coflow_validation(dem_damping_curve damping dem_two_sphere_impact.yaml 1 0.0 0.05 0.1 0.2 0.4 0.7)
# The same impact in a box of 1 m (942^3 cells of the contact search) on 2
# ranks, under 4 GB of address space: the cells cover the particles on each
# rank, not the box (a grid of the whole box with its neighbour lists,
# about 250 bytes a cell per rank, failed with bad_alloc before 2026-12-05).
add_test(NAME validation.dem_two_sphere_impact_large_box
  COMMAND sh -c "ulimit -v 4000000 && exec \"$0\" \"$@\"" ${validate} dem_two_sphere_impact_large_box
          ${CMAKE_BINARY_DIR}/bin ${CMAKE_CURRENT_BINARY_DIR}/val-dem_two_sphere_impact_large_box impact
          ${vcfg}/dem_two_sphere_impact.yaml --set domain.upper=[1.0,1.0,1.0] --set particles.ranks=2 --set
          [=[particles.initial=[{"single":{"species":"grain","position":[0.4995,0.5,0.5],"velocity":[0.1,0,0]}},{"single":{"species":"grain","position":[0.500502,0.5,0.5],"velocity":[-0.1,0,0]}}]]=])
set_tests_properties(validation.dem_two_sphere_impact_large_box PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
# The same box with two more grains in far corners: a rank's particles then
# span most of the box, whose cells are kept sparse (sorted, by bisection);
# dem on 2 ranks against dem-reference, under 4 GB.
set(far_corners [=[particles.initial=[{"single":{"species":"grain","position":[0.4995,0.5,0.5],"velocity":[0.1,0,0]}},{"single":{"species":"grain","position":[0.500502,0.5,0.5],"velocity":[-0.1,0,0]}},{"single":{"species":"grain","position":[0.95,0.05,0.05]}},{"single":{"species":"grain","position":[0.05,0.95,0.95]}}]]=])
add_test(NAME validation.dem_sparse_cells_vs_reference
  COMMAND sh -c "ulimit -v 4000000 && exec \"$0\" \"$@\"" ${validate} dem_sparse_cells_vs_reference
          ${CMAKE_BINARY_DIR}/bin ${CMAKE_CURRENT_BINARY_DIR}/val-dem_sparse_cells_vs_reference compare
          ${vcfg}/dem_two_sphere_impact.yaml
          "domain.upper=[1.0,1.0,1.0] particles.ranks=2 run.output.every=8.0e-5 ${far_corners}"
          "domain.upper=[1.0,1.0,1.0] particles.solver=dem-reference run.output.every=8.0e-5 ${far_corners}")
set_tests_properties(validation.dem_sparse_cells_vs_reference PROPERTIES LABELS "validation;mpi" PROCESSORS 2)
coflow_validation(dem_vs_reference compare dem_crosscheck.yaml 1 "particles.solver=dem" "particles.solver=dem-reference")
coflow_validation(dem_vs_reference_bonded compare dem_crosscheck_bonded.yaml 1 "particles.solver=dem" "particles.solver=dem-reference")
coflow_validation(dem_gravity_pour pour dem_gravity_pour.yaml 1)
# Fixed grains given on the upper face of a periodic axis (x = 0.02 in
# dem_ranks.yaml), among 500 falling ones: both variants start them on the
# lower face (dem-reference wrapped them at its first step, dem never did,
# before 2026-12-05).
set(fixed_upper [=[particles.species={"grain":{"density":2650.0,"diameter":{"uniform":{"min":0.8e-3,"max":1.2e-3}}},"post":{"density":2650.0,"diameter":2.0e-3,"fixed":true}} particles.initial=[{"random":{"species":"grain","count":500,"region":{"lower":[0.0,0.0,0.0],"upper":[0.02,0.02,0.04]},"velocity_std":0.5}},{"single":{"species":"post","position":[0.02,0.01,0.002]}},{"single":{"species":"post","position":[0.02,0.013,0.002]}}]]=])
coflow_validation(dem_fixed_on_periodic_face_vs_reference compare dem_ranks.yaml 1
  "particles.solver=dem ${fixed_upper}" "particles.solver=dem-reference ${fixed_upper}")
# Bonds breaking and grains crushing on 4 ranks as on 1; and with the automatic
# step, crushed (lighter) grains split the step alike in dem and dem-reference.
coflow_validation(dem_bonded_ranks_1_vs_4 compare dem_crosscheck_bonded.yaml 2
  "particles.ranks=1" "particles.ranks=4 particles.decomposition=[2,2,1]")
# Crushing by a fifth of the radius widens a crushed grain's other bonds past
# the neighbour list's cut: they must still fail in tension, counted and
# logged, on 4 ranks as on 1 (before 2026-12-03, 4 ranks logged 270 of 396).
coflow_validation(dem_crushing_ranks_1_vs_4 compare dem_crosscheck_bonded.yaml 2
  "particles.ranks=1 particles.contact.bond.crush_fraction=0.2"
  "particles.ranks=4 particles.decomposition=[2,2,1] particles.contact.bond.crush_fraction=0.2")
# No particle at all (a box that an upstream stage fills later): dem runs, on
# 1 rank and on 4 (before 2026-12-03 its cells were sized by the bond gap
# alone and their count overflowed: std::bad_alloc).
coflow_validation(dem_no_particles_ranks_1_vs_4 compare dem_crosscheck_bonded.yaml 2
  "particles.ranks=1 particles.initial=[]" "particles.ranks=4 particles.decomposition=[2,2,1] particles.initial=[]")
# A checkpoint of dem on 2 ranks (cut along y: the file holds rank 0's
# particles, then rank 1's, not in id order) restarts dem-reference on 1 rank
# bit for bit (before 2026-12-03 its pair order, and so the velocities, moved
# by 4.6e-16: it kept the file's order).
coflow_validation(dem_reference_restart_from_dem_2_ranks restart_from dem_crosscheck_bonded.yaml 2
  5.0e-4 "particles.ranks=2 particles.decomposition=[1,2,1] run.output.series_every=2.5e-4"
  "particles.solver=dem-reference run.output.series_every=2.5e-4")
coflow_validation(dem_crushing_auto_step crush dem_crosscheck_bonded.yaml 1
  --set particles.time_step=auto --set particles.contact.bond.crush_fraction=0.2)
coflow_validation(dem_crushing_auto_step_vs_reference compare dem_crosscheck_bonded.yaml 1
  "particles.time_step=auto particles.contact.bond.crush_fraction=0.2 particles.solver=dem"
  "particles.time_step=auto particles.contact.bond.crush_fraction=0.2 particles.solver=dem-reference")
coflow_validation(dem_ranks_1_vs_4 compare dem_ranks.yaml 2
  "particles.ranks=1" "particles.ranks=4 particles.decomposition=[2,2,1]")
coflow_validation(dem_mesh_vs_face compare dem_mesh_wall.yaml 1
  "particles.solver=dem" "particles.walls=[] particles.boundaries.z-=wall domain.lower=[0,0,0.001]")
coflow_validation(dem_mesh_vs_reference compare dem_mesh_wall.yaml 1 "particles.solver=dem" "particles.solver=dem-reference")
# The sphere slides across x = 10 mm, the cut between the two ranks, while it
# touches the mesh: its contact history (spring and direction) moves with it.
coflow_validation(dem_mesh_ranks_1_vs_2 compare dem_mesh_wall.yaml 2
  "particles.ranks=1" "particles.ranks=2 particles.decomposition=[2,1,1]")
coflow_validation(dem_outlet_vs_reference compare dem_outlet.yaml 1 "particles.solver=dem" "particles.solver=dem-reference")
coflow_validation(dem_outlet_1_vs_3 compare dem_outlet.yaml 2
  "particles.ranks=1" "particles.ranks=3 particles.decomposition=[1,1,3]")
# Forces on walls (series/walls.csv): the momentum balance of grains in a
# closed box, dem and its reference, dpm and its reference, and dem on 4 ranks.
coflow_validation(particles_walls_dem walls particles_box_walls.yaml 1)
coflow_validation(particles_walls_dem_reference walls particles_box_walls.yaml 1 --set particles.solver=dem-reference)
coflow_validation(particles_walls_dem_4_ranks walls particles_box_walls.yaml 1 --set particles.ranks=4)
coflow_validation(particles_walls_dpm walls particles_box_walls_dpm.yaml 1)
coflow_validation(particles_walls_dpm_reference walls particles_box_walls_dpm.yaml 1 --set particles.solver=dpm-reference)
# The x+ face a symmetry plane: its reflections are mirrors, no wall impacts.
coflow_validation(particles_walls_dpm_symmetry walls particles_box_walls_dpm.yaml 1
  --set particles.boundaries.x+=symmetry --set run.output.collision_events=true)
coflow_validation(particles_walls_dpm_symmetry_reference walls particles_box_walls_dpm.yaml 1
  --set particles.boundaries.x+=symmetry --set run.output.collision_events=true --set particles.solver=dpm-reference)
