# The finite-volume fluid (fv, fv-reference; issue 21): exact steady channel
# and Couette profiles, Taylor-Green decay and its orders in space and time,
# divergence after the projection, the lid-driven cavity against Ghia, Ghia &
# Shin 1982, and the crosschecks (fv against fv-reference, 1 rank against N).
# Included from tests/CMakeLists.txt (validation/tests.cmake).
coflow_validation(fv_poiseuille_force profile fv_poiseuille_force.yaml 1)
coflow_validation(fv_poiseuille_pressure profile fv_poiseuille_pressure.yaml 1)
coflow_validation(fv_couette profile fv_couette.yaml 1)
coflow_validation(fv_taylor_green decay fv_taylor_green.yaml 2)
coflow_validation(fv_taylor_green_error tg_error fv_taylor_green.yaml 2)
coflow_validation(fv_taylor_green_divergence divergence fv_taylor_green.yaml 2)
# Space: 16, 32, 64 cells with a step small enough (0.25 s) that the time error
# is far below the space error. Time: on one grid, steps 2, 1, 0.5, 0.25 s (the
# CFL step is 2.5 s), successive runs' differences.
coflow_validation(fv_taylor_green_order_space order_tg fv_taylor_green.yaml 1
  "domain.cells=[16,16,1] fluid.fv.max_step=0.25 fluid.ranks=1"
  "domain.cells=[32,32,1] fluid.fv.max_step=0.25 fluid.ranks=1"
  "domain.cells=[64,64,1] fluid.fv.max_step=0.25 fluid.ranks=1")
foreach(scheme sbdf2 cnab2)
  coflow_validation(fv_taylor_green_order_time_${scheme} order_time fv_taylor_green.yaml 1
    "fluid.fv.time=${scheme} fluid.fv.cfl=1.0 fluid.fv.max_step=2.0 fluid.ranks=1"
    "fluid.fv.time=${scheme} fluid.fv.cfl=1.0 fluid.fv.max_step=1.0 fluid.ranks=1"
    "fluid.fv.time=${scheme} fluid.fv.cfl=1.0 fluid.fv.max_step=0.5 fluid.ranks=1"
    "fluid.fv.time=${scheme} fluid.fv.cfl=1.0 fluid.fv.max_step=0.25 fluid.ranks=1")
endforeach()
coflow_validation(fv_all_boundaries_divergence divergence fv_all_boundaries_3d.yaml 1)
# 1 rank against 4, the blocks cut along each axis (the open x+ face's
# velocity crosses the y and z cuts; z is periodic).
foreach(dec "2,2,1" "4,1,1" "1,2,2")
  string(REPLACE "," "" tag ${dec})
  coflow_validation(fv_ranks_1_vs_4_${tag} compare fv_all_boundaries_3d.yaml 4
    "fluid.ranks=1" "fluid.ranks=4 fluid.decomposition=[${dec}]")
endforeach()
coflow_validation(fv_ranks_1_vs_2_taylor_green compare fv_taylor_green.yaml 2
  "fluid.ranks=1" "fluid.ranks=2")
# fv against fv-reference (plain loops, unpreconditioned CG): every face kind
# with upwind advection and SBDF2, then central non-divergent advection with
# CNAB2; the periodic Taylor-Green vortex with the solves at 1e-13.
coflow_validation(fv_vs_reference compare fv_all_boundaries_3d.yaml 1
  "fluid.solver=fv" "fluid.solver=fv-reference")
# fv and fv-reference write one checkpoint format: each restarts from the
# other's first checkpoint and ends where its own straight run ends, to round-off.
coflow_validation(fv_restart_from_reference restart_from fv_all_boundaries_3d.yaml 1
  10.0 "fluid.solver=fv-reference" "fluid.solver=fv")
coflow_validation(fv_reference_restart_from_fv restart_from fv_all_boundaries_3d.yaml 1
  10.0 "fluid.solver=fv" "fluid.solver=fv-reference")
coflow_validation(fv_vs_reference_cnab2_central compare fv_all_boundaries_3d.yaml 1
  "fluid.solver=fv fluid.fv.time=cnab2 fluid.fv.advection=central fluid.fv.form=non-divergent"
  "fluid.solver=fv-reference fluid.fv.time=cnab2 fluid.fv.advection=central fluid.fv.form=non-divergent")
set(fv_tg_sets "fluid.ranks=1 fluid.fv.tolerance=1e-13 fluid.fv.advection=upwind run.end_time=50.0 run.output.every=50.0")
coflow_validation(fv_vs_reference_taylor_green compare fv_taylor_green.yaml 1
  "fluid.solver=fv ${fv_tg_sets}" "fluid.solver=fv-reference ${fv_tg_sets}")
# Two-way momentum exchange with point particles (seed 003 §5.1) on fv: the
# velocities against eqs 5.2-5.3, fluid + particle momentum kept (eq. 5.6)
# with SBDF2 (the source enters as an exact impulse) and CNAB2; at Re_p 0.004
# against the closed form of eqs 5.4-5.5; and the same case on fv against lbm.
coflow_validation(dpm_two_way_fv two_way dpm_two_way_fv.yaml 3)
coflow_validation(dpm_two_way_fv_cnab2 two_way dpm_two_way_fv.yaml 3 --set fluid.fv.time=cnab2)
set(fv_stokes_start "particles.initial=[{lattice: {species: droplet, spacing: 0.1, region: {lower: [0.0, 0.0, 0.0], upper: [1.0, 1.0, 1.0]}, velocity: [0.001, 0.0, 0.0]}}]")
coflow_validation(dpm_two_way_fv_stokes two_way dpm_two_way_fv.yaml 3 --set "${fv_stokes_start}")
coflow_validation(dpm_two_way_fv_vs_lbm compare dpm_two_way.yaml 3 "config=dpm_two_way.yaml" "config=dpm_two_way_fv.yaml")
# The lid-driven cavity at 128^2 against Ghia, Ghia & Shin 1982 (Tables I, II),
# on one rank (the configs' two took 1.47x the core-seconds for the same
# metrics, 2026-12-06; ranks are fv_ranks_1_vs_2_*'s subject).
coflow_validation(fv_cavity_re100 cavity fv_cavity_re100.yaml 1 --set fluid.ranks=1)
coflow_validation(fv_cavity_re1000 cavity fv_cavity_re1000.yaml 1 --set fluid.ranks=1)
# Symmetry faces: the lower half of a force-driven channel (wall at y-,
# symmetry at y+) against the full channel's parabola, exact to round-off
# after 12000 s (30 decay times of its slowest mode); fv against fv-reference
# and 1 rank against 4 with symmetry faces at z- and z+.
coflow_validation(fv_half_channel_symmetry profile fv_poiseuille_force.yaml 1
  --set fluid.boundaries.y+.type=symmetry --set run.end_time=12000.0 --set run.output.every=12000.0)
set(fv_sym_sets "domain.periodic=[false,false,false] fluid.boundaries.z-.type=symmetry fluid.boundaries.z+.type=symmetry fluid.body_force=[1.0e-3,0.0,0.0]")
coflow_validation(fv_vs_reference_symmetry compare fv_all_boundaries_3d.yaml 1
  "fluid.solver=fv ${fv_sym_sets}" "fluid.solver=fv-reference ${fv_sym_sets}")
coflow_validation(fv_ranks_1_vs_4_symmetry compare fv_all_boundaries_3d.yaml 4
  "fluid.ranks=1 ${fv_sym_sets}" "fluid.ranks=4 fluid.decomposition=[1,2,2] ${fv_sym_sets}")
# A parabolic velocity inlet and an outflow face: plane Poiseuille flow from
# the inlet on; fv against fv-reference and 1 rank against 2 (the inlet's
# profile cut between blocks) at 400 s, still developing.
coflow_validation(fv_channel_inlet profile fv_channel_inlet.yaml 1)
set(fv_inlet_sets "run.end_time=400.0 run.output.every=400.0")
coflow_validation(fv_vs_reference_inlet compare fv_channel_inlet.yaml 1
  "fluid.solver=fv ${fv_inlet_sets}" "fluid.solver=fv-reference ${fv_inlet_sets}")
coflow_validation(fv_ranks_1_vs_2_inlet compare fv_channel_inlet.yaml 2
  "fluid.ranks=1 ${fv_inlet_sets}" "fluid.ranks=2 fluid.decomposition=[1,2,1] ${fv_inlet_sets}")
# The same inlet as a table of the parabola at the cells' centres (profile:
# table): Poiseuille flow again, and the tabulated face read alike by fv and
# fv-reference.
set(fv_inlet_table "fluid.boundaries.x-.profile=table fluid.boundaries.x-.profile_file=profiles/channel_parabola_32.csv")
coflow_validation(fv_channel_inlet_table profile fv_channel_inlet.yaml 1
  --set fluid.boundaries.x-.profile=table --set fluid.boundaries.x-.profile_file=profiles/channel_parabola_32.csv)
coflow_validation(fv_vs_reference_inlet_table compare fv_channel_inlet.yaml 1
  "fluid.solver=fv ${fv_inlet_sets} ${fv_inlet_table}" "fluid.solver=fv-reference ${fv_inlet_sets} ${fv_inlet_table}")
# The inlet's parabola as a formula (profile: expression; its factor 1 + 100 x
# is 1 only on the face itself, where the formula must be evaluated), and a face whose
# formula is in time: Stokes' oscillating wall against the gap's exact
# periodic solution, its order in space (16, 32, 64 cells across the gap, the
# step small enough that the space error dominates), fv against fv-reference.
coflow_validation(fv_channel_inlet_expression profile fv_channel_inlet.yaml 1
  --set fluid.boundaries.x-.profile=expression --set "fluid.boundaries.x-.profile_expression=4*(y/0.032)*(1-y/0.032)*(1+100*x)")
# A formula defined inside the box only (sqrt of a negative beyond the walls,
# where the ghost lines ask for it): its fractions are held to the box.
coflow_validation(fv_channel_inlet_expression_inside profile fv_channel_inlet.yaml 1
  --set fluid.boundaries.x-.profile=expression --set "fluid.boundaries.x-.profile_expression=sqrt(4*(y/0.032)*(1-y/0.032))^2")
coflow_validation(fv_stokes_layer stokes_layer fv_stokes_layer.yaml 1)
coflow_validation(fv_stokes_layer_order order_stokes fv_stokes_layer.yaml 1
  "domain.cells=[4,16,1] domain.upper=[0.05,0.2,0.0125]"
  "domain.cells=[4,32,1] domain.upper=[0.025,0.2,0.00625]"
  "domain.cells=[4,64,1] domain.upper=[0.0125,0.2,0.003125]")
coflow_validation(fv_vs_reference_stokes_layer compare fv_stokes_layer.yaml 1
  "fluid.solver=fv run.end_time=2.25 run.output.every=2.25" "fluid.solver=fv-reference run.end_time=2.25 run.output.every=2.25")
# k-epsilon with the two-layer wall model (issue 22): decaying homogeneous
# turbulence against the model's exact solution (and with C_e2 changed), the
# decay behind a grid (seed 003 §5.4's carrier flow) against the model's exact
# decay from the inlet, the channel at Re_tau 392 against Moser, Kim & Mansour's
# DNS and Dean's skin friction; 1 rank against 2 (the grid flow cut along x,
# the channel across the walls' layers).
coflow_validation(fv_ke_decay ke_decay fv_ke_decay.yaml 1)
coflow_validation(fv_ke_decay_ce2_1_8 ke_decay fv_ke_decay.yaml 1 --set fluid.turbulence.constants.C_epsilon2=1.8)
coflow_validation(fv_ke_grid_turbulence ke_grid fv_ke_grid_turbulence.yaml 1)
coflow_validation(fv_ke_channel ke_channel fv_ke_channel.yaml 1)
coflow_validation(fv_ke_ranks_1_vs_2_grid compare fv_ke_grid_turbulence.yaml 2
  "fluid.ranks=1 run.end_time=0.5 run.output.every=0.5" "fluid.ranks=2 fluid.decomposition=[2,1,1] run.end_time=0.5 run.output.every=0.5")
coflow_validation(fv_ke_ranks_1_vs_2_channel compare fv_ke_channel.yaml 2
  "fluid.ranks=1 run.end_time=8.0 run.output.every=8.0" "fluid.ranks=2 fluid.decomposition=[1,2,1] run.end_time=8.0 run.output.every=8.0")
# fv against fv-reference with k-epsilon: every face kind in 3D, and the
# channel with the two-layer model (100 cells, while it develops); 1 rank
# against 4 in 3D.
coflow_validation(fv_ke_vs_reference compare fv_ke_all_boundaries_3d.yaml 1
  "fluid.solver=fv" "fluid.solver=fv-reference")
# The same turned a quarter: walls on x, the upper open face on y (the
# corner ghosts beyond both).
coflow_validation(fv_ke_vs_reference_corners compare fv_ke_corners_3d.yaml 1
  "fluid.solver=fv" "fluid.solver=fv-reference")
# The moving wall (y+) with a parabolic profile: the wall cells' y+ takes the
# wall's own velocity at each place in both.
coflow_validation(fv_ke_vs_reference_profiled_wall compare fv_ke_all_boundaries_3d.yaml 1
  "fluid.solver=fv fluid.boundaries.y+.profile=parabolic" "fluid.solver=fv-reference fluid.boundaries.y+.profile=parabolic")
set(fv_ke_ch_sets "domain.cells=[4,100,1] run.end_time=4.0 run.output.every=4.0 fluid.fv.tolerance=1e-13")
coflow_validation(fv_ke_vs_reference_channel compare fv_ke_channel.yaml 1
  "fluid.solver=fv ${fv_ke_ch_sets}" "fluid.solver=fv-reference ${fv_ke_ch_sets}")
# The same with Crank-Nicolson / Adams-Bashforth: the walls' deferred u1 is
# extrapolated to the new time in both (Imex::e0, e1).
coflow_validation(fv_ke_vs_reference_channel_cnab2 compare fv_ke_channel.yaml 1
  "fluid.solver=fv ${fv_ke_ch_sets} fluid.fv.time=cnab2" "fluid.solver=fv-reference ${fv_ke_ch_sets} fluid.fv.time=cnab2")
coflow_validation(fv_ke_ranks_1_vs_4 compare fv_ke_all_boundaries_3d.yaml 4
  "fluid.ranks=1" "fluid.ranks=4 fluid.decomposition=[2,2,1]")
# The wall functions (wall: log-law): the channel at Re_tau 392 with 12
# cells against the DNS and Dean's skin friction; fv against fv-reference
# and 1 rank against 2 and 4: the channel, a duct with a sliding wall and
# corners (the log law's branch in 3D), every face kind in 3D (its wall cells
# in the viscous branch, y* below 11.53).
coflow_validation(fv_ke_log_law_channel ke_channel fv_ke_channel_log_law.yaml 1)
set(fv_ke_ll_sets "run.end_time=4.0 run.output.every=4.0 fluid.fv.tolerance=1e-13")
coflow_validation(fv_ke_log_law_vs_reference_channel compare fv_ke_channel_log_law.yaml 1
  "fluid.solver=fv ${fv_ke_ll_sets}" "fluid.solver=fv-reference ${fv_ke_ll_sets}")
coflow_validation(fv_ke_log_law_ranks_1_vs_2_channel compare fv_ke_channel_log_law.yaml 2
  "fluid.ranks=1 ${fv_ke_ll_sets}" "fluid.ranks=2 fluid.decomposition=[1,2,1] ${fv_ke_ll_sets}")
coflow_validation(fv_ke_log_law_duct_vs_reference compare fv_ke_duct_log_law.yaml 1
  "fluid.solver=fv" "fluid.solver=fv-reference")
coflow_validation(fv_ke_log_law_duct_ranks_1_vs_4 compare fv_ke_duct_log_law.yaml 4
  "fluid.ranks=1" "fluid.ranks=4 fluid.decomposition=[1,2,2]")
coflow_validation(fv_ke_log_law_vs_reference compare fv_ke_all_boundaries_3d.yaml 1
  "fluid.solver=fv fluid.turbulence.wall=log-law" "fluid.solver=fv-reference fluid.turbulence.wall=log-law")
coflow_validation(fv_ke_log_law_ranks_1_vs_4 compare fv_ke_all_boundaries_3d.yaml 4
  "fluid.ranks=1 fluid.turbulence.wall=log-law" "fluid.ranks=4 fluid.decomposition=[2,2,1] fluid.turbulence.wall=log-law")
# The backward-facing step of Driver & Seegmiller (1985) with wall
# functions: the reattachment length (the config's grid, to t = 100 H/U:
# x_r moves by 0.1 % from t = 100 to 160).
coflow_validation(fv_ke_backward_step ke_backward_step fv_ke_backward_step.yaml 1
  --set run.end_time=100.0 --set run.output.every=100.0)
# The same step on 160 x 72 cells against OpenFOAM's simpleFoam with the
# same model on the same grid (scripts/openfoam_backward_step.sh, 600 SIMPLE
# iterations): a second implementation of the standard k-epsilon model and
# its wall functions; fv to t = 160, and on from its checkpoint there to
# 240 H/U (settled). Skipped where
# OpenFOAM is not installed.
coflow_validation(fv_ke_backward_step_openfoam openfoam_backward_step fv_ke_backward_step.yaml 1 160 72 600 160 240)
set_tests_properties(validation.fv_ke_backward_step_openfoam PROPERTIES SKIP_RETURN_CODE 77)
# k and epsilon per inlet face: two inlets bringing different ones (x- its
# own, y+ turbulence.inlet's), fv against fv-reference; and a face's own
# values, equal to the config's turbulence.inlet, with turbulence.inlet
# changed, give the same run as turbulence.inlet alone (the face's are used).
set(fv_ke_faces "fluid.boundaries.y+.value=[1.0e-3,-2.0e-4,5.0e-4] fluid.boundaries.x-.k=8.0e-6 fluid.boundaries.x-.epsilon=3.0e-7")
coflow_validation(fv_ke_face_inlets_vs_reference compare fv_ke_all_boundaries_3d.yaml 1
  "fluid.solver=fv ${fv_ke_faces}" "fluid.solver=fv-reference ${fv_ke_faces}")
coflow_validation(fv_ke_face_inlet_used compare fv_ke_all_boundaries_3d.yaml 1 "fluid.solver=fv"
  "fluid.solver=fv fluid.turbulence.inlet.k=9.0e-6 fluid.turbulence.inlet.epsilon=5.0e-7 fluid.boundaries.x-.k=4.0e-6 fluid.boundaries.x-.epsilon=2.0e-7")
# k and epsilon from a turbulence intensity and a mixing length, following
# the inlet's speed along its parabolic profile and ramp (x-): fv against
# fv-reference, and 1 rank against 4; with a uniform, unramped inlet the
# same run as the face's k and epsilon computed by hand from the two
# formulas (k = 3/2 (I U)^2 = 1.5e-6 for I = 0.5, U = 2e-3 m/s; epsilon =
# 0.09^(3/4) k^(3/2) / L = 3.0186917696247164e-7 for L = 1 mm).
set(fv_ke_intensity "fluid.boundaries.x-.intensity=0.05 fluid.boundaries.x-.mixing_length=2.0e-3")
coflow_validation(fv_ke_intensity_vs_reference compare fv_ke_all_boundaries_3d.yaml 1
  "fluid.solver=fv ${fv_ke_intensity}" "fluid.solver=fv-reference ${fv_ke_intensity}")
coflow_validation(fv_ke_intensity_ranks_1_vs_4 compare fv_ke_all_boundaries_3d.yaml 4
  "fluid.ranks=1 ${fv_ke_intensity}" "fluid.ranks=4 fluid.decomposition=[2,2,1] ${fv_ke_intensity}")
set(fv_ke_uniform_inlet "fluid.boundaries.x-.profile=uniform fluid.boundaries.x-.ramp=0")
coflow_validation(fv_ke_intensity_used compare fv_ke_all_boundaries_3d.yaml 1
  "${fv_ke_uniform_inlet} fluid.boundaries.x-.k=1.5e-6 fluid.boundaries.x-.epsilon=3.0186917696247164e-7"
  "${fv_ke_uniform_inlet} fluid.boundaries.x-.intensity=0.5 fluid.boundaries.x-.mixing_length=1.0e-3")
# k and epsilon tabulated across the inlet (turbulence_file, rows y, k,
# epsilon): fv against fv-reference; and a table with the same values in every
# row gives the run with those as the face's k and epsilon.
set(fv_ke_table "fluid.boundaries.x-.turbulence_file=fv_ke_inlet_profile.csv")
coflow_validation(fv_ke_table_vs_reference compare fv_ke_all_boundaries_3d.yaml 1
  "fluid.solver=fv ${fv_ke_table}" "fluid.solver=fv-reference ${fv_ke_table}")
coflow_validation(fv_ke_table_used compare fv_ke_all_boundaries_3d.yaml 1
  "fluid.boundaries.x-.k=1.5e-6 fluid.boundaries.x-.epsilon=3.0186917696247164e-7"
  "fluid.boundaries.x-.turbulence_file=fv_ke_inlet_constant.csv")
# The convective outflow face lets a vortex leave: against the same flow in a
# box twice as long (issue 21), and a pressure face (zero gradient) for scale.
coflow_validation(fv_outflow_vortex reflection fv_outflow_vortex.yaml 1 "fluid.boundaries.x+.type=outflow"
  "domain.upper=[2.0,1.0,0.015625] domain.cells=[128,64,1]"
  "fluid.boundaries.x+.type=pressure fluid.boundaries.x+.value=0.0")
# fv on the adaptive grid (fluid.fv.refinement, issue 25): a vortex carried
# across a periodic box and followed by vorticity refinement, against the
# exact viscous solution; 1 rank against 2 with regridding; the seed's
# two-way momentum case with the particles drifting across a level boundary.
coflow_validation(fv_amr_vortex vortex fv_amr_vortex.yaml 1)
# The same with the composite grid's diffusion implicit (fluid.fv.refinement.diffusion).
coflow_validation(fv_amr_vortex_implicit vortex fv_amr_vortex.yaml 1 --set fluid.fv.refinement.diffusion=implicit
  --set run.end_time=0.25 --set run.output.every=0.25)
coflow_validation(fv_amr_vortex_implicit_ranks compare fv_amr_vortex.yaml 2
  "fluid.ranks=1 run.end_time=0.15 run.output.every=0.15 fluid.fv.refinement.diffusion=implicit"
  "fluid.ranks=2 run.end_time=0.15 run.output.every=0.15 fluid.fv.refinement.diffusion=implicit")
coflow_validation(fv_amr_vortex_ranks compare fv_amr_vortex.yaml 2
  "fluid.ranks=1 run.end_time=0.15 run.output.every=0.15" "fluid.ranks=2 run.end_time=0.15 run.output.every=0.15")
# k-epsilon on the adaptive grid (composite_turbulence.hpp): decaying
# homogeneous turbulence across a coarse-fine box, the decay behind a grid
# through fine-coarse-fine-coarse levels (every leaf cell against the exact
# decay), and 1 rank against 2 with walls, an inlet, an outflow and a regrid.
coflow_validation(fv_amr_ke_decay ke_decay fv_amr_ke_decay.yaml 1)
coflow_validation(fv_amr_ke_grid_turbulence ke_grid_levels fv_amr_ke_grid_turbulence.yaml 1)
coflow_validation(fv_amr_ke_ranks_1_vs_2 compare fv_amr_ke_inlet_walls.yaml 2 "fluid.ranks=1" "fluid.ranks=2")
# A wall sliding along itself (y+ at 0.5 m/s) given with a profile (here the
# formula 1) is a wall as without one: fv and fv-reference took it so, the
# adaptive grid took it as an inlet before 2026-12-07 (k and epsilon held at
# the inlet's values there, no two-layer cells beside it: k 4.1 apart).
set(fv_amr_sliding "fluid.boundaries.y+.type=velocity fluid.boundaries.y+.value=[0.5,0.0,0.0]")
# A uniform fluid.initial.pressure sets no level on the adaptive grid (its
# implicit first step took it as the old pressure before 2026-12-07: a jump
# of P over half a cell at the outflow face x+).
coflow_validation(fv_amr_ke_initial_pressure_level compare fv_amr_ke_inlet_walls.yaml 1 ""
  "fluid.initial.pressure=101325")
coflow_validation(fv_amr_ke_profiled_sliding_wall compare fv_amr_ke_inlet_walls.yaml 1 "${fv_amr_sliding}"
  "${fv_amr_sliding} fluid.boundaries.y+.profile=expression fluid.boundaries.y+.profile_expression=1")
# The adaptive grid takes an inlet face's own k and epsilon (as
# fv_ke_face_inlet_used), the inlet on x+ (not the first face, index 0).
coflow_validation(fv_amr_ke_face_inlet_used compare fv_amr_ke_inlet_x_plus.yaml 1 "fluid.ranks=1"
  "fluid.ranks=1 fluid.turbulence.inlet.k=0.03 fluid.turbulence.inlet.epsilon=0.01 fluid.boundaries.x+.k=0.015 fluid.boundaries.x+.epsilon=0.006")
# The same on the adaptive grid: the inlet's turbulence intensity 0.1 and
# mixing length 0.05031152949374528 m give k = 1.5 (0.1 x 1 m/s)^2 = 0.015 and
# epsilon = 0.09^(3/4) k^(3/2) / L = 0.006, this file's turbulence.inlet
# (then changed); and with a parabolic inlet, 1 rank against 2.
coflow_validation(fv_amr_ke_intensity_used compare fv_amr_ke_inlet_x_plus.yaml 1 "fluid.ranks=1"
  "fluid.ranks=1 fluid.turbulence.inlet.k=0.03 fluid.turbulence.inlet.epsilon=0.01 fluid.boundaries.x+.intensity=0.1 fluid.boundaries.x+.mixing_length=0.05031152949374528")
set(fv_amr_ke_intensity "fluid.boundaries.x-.profile=parabolic fluid.boundaries.x-.intensity=0.1 fluid.boundaries.x-.mixing_length=0.05")
coflow_validation(fv_amr_ke_intensity_ranks_1_vs_2 compare fv_amr_ke_inlet_walls.yaml 2
  "fluid.ranks=1 ${fv_amr_ke_intensity}" "fluid.ranks=2 ${fv_amr_ke_intensity}")
coflow_validation(fv_amr_ke_table_used compare fv_amr_ke_inlet_x_plus.yaml 1 "fluid.ranks=1"
  "fluid.ranks=1 fluid.turbulence.inlet.k=0.03 fluid.turbulence.inlet.epsilon=0.01 fluid.boundaries.x+.turbulence_file=fv_amr_ke_inlet_constant.csv")
coflow_validation(fv_amr_ke_table_ranks_1_vs_2 compare fv_amr_ke_inlet_walls.yaml 2
  "fluid.ranks=1 fluid.boundaries.x-.turbulence_file=fv_amr_ke_inlet_profile.csv"
  "fluid.ranks=2 fluid.boundaries.x-.turbulence_file=fv_amr_ke_inlet_profile.csv")
coflow_validation(dpm_two_way_amr two_way dpm_two_way_amr.yaml 3)
# The same with implicit diffusion: the point particles' momentum source on
# two levels through the implicit step (its advective part); momentum then to
# the Helmholtz solves' tolerance, not round-off.
coflow_validation(dpm_two_way_amr_implicit two_way dpm_two_way_amr.yaml 3
  --set fluid.fv.refinement.diffusion=implicit)
