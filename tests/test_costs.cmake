# Seconds each long test took in a whole-suite run (ctest -j2, 2-core AMD
# EPYC VM, 2026-11-27), as its COST: ctest starts the costliest tests first, so
# that a fresh build directory (no Testing/Temporary/CTestCostData.txt yet)
# does not end on a long test running alone. Ordering only; tests of 8 s or
# more (the tests added since, unit.amr_cavity_implicit and the *_implicit
# validations, and those shortened on 2026-11-28: unit.amr, the grain
# interface, the capillary bridge and E4, timed alone or scaled by their
# steps; the k-epsilon tests of the adaptive grid and unit.mpi with them,
# 2026-11-28, in ctest -j2 beside others; the DFG tests and the Slurm test
# from the whole-suite run of 2026-12-06, session 71; those changed on
# 2026-12-06, session 74, in ctest -j2 beside each other). Included by tests/CMakeLists.txt after every
# test is defined; a name that is no test is reported.
set(coflow_test_costs
  validation.lbm_dfg_cylinder 23
  validation.lbm_dfg_cylinder_2d2 31
  validation.lbm_dfg_cylinder_halfway 23
  validation.ibm_cylinder_re20 80
  validation.two_phase_laplace_3d 35
  unit.mpi 28
  unit.mpi_4_ranks 16
  validation.psm_settling_sphere_e4 68
  validation.ibm_cylinder_re100 62
  validation.two_phase_grain_interface_120 50
  validation.two_phase_grain_interface_60 50
  validation.dpm_granular_gas_bidisperse 28
  validation.fv_ke_channel 46
  validation.fv_ke_backward_step 40
  validation.fv_ke_backward_step_openfoam 24
  validation.two_phase_capillary_bridge 45
  validation.psm_settling_sphere_e3 56
  validation.psm_settling_sphere_e2 42
  validation.psm_settling_sphere_e1 46
  validation.fv_cavity_re1000 28
  validation.ibm_sphere_re100 43
  validation.dpm_grid_turbulence_fv 32
  unit.amr_cavity 30
  validation.lbm_duct_3d_pressure 20
  validation.dpm_grid_turbulence_ct026 28
  validation.dpm_grid_turbulence 27
  cluster.srun_quickstart 14
  unit 25
  validation.dem_gravity_pour 25
  validation.ibm_cylinder_re20_lbm 24
  validation.fv_cavity_re100 16
  validation.ibm_cylinder_oscillating 23
  validation.dpm_dispersion 23
  validation.solids_sphere_array_tau 22
  unit.amr_cavity_implicit 20
  validation.dpm_jet_plate 20
  validation.solids_sphere_array 20
  validation.solids_sphere_array_interpolated 20
  validation.solids_sphere_array_central 20
  validation.solids_sphere_array_tau_central 22
  validation.psm_walls_variants 27
  validation.dpm_mesh_vs_reference 19
  validation.ibm_ranks_1_vs_16_moving 19
  validation.dem_outlet_vs_reference 18
  validation.psm_drag_array 17
  validation.dpm_vs_reference 17
  validation.dpm_granular_gas 17
  validation.two_phase_washburn 16
  unit.amr 15
  validation.ibm_lbm_vs_reference_fixed 15
  validation.ibm_cylinder_amr_implicit 15
  validation.fv_amr_ke_grid_turbulence 15
  validation.fv_amr_ke_decay 14
  validation.ibm_cylinder_frames 14
  validation.ibm_couette_peskin4 15
  validation.ibm_couette_oscillating 13
  validation.ibm_couette 6
  validation.ibm_couette_hat 6
  validation.dem_damping_curve 14
  validation.ibm_cylinder_amr 14
  restart.dem_2_ranks 14
  restart.damaged_checkpoints 27
  restart.ibm_translating 13
  validation.fv_amr_vortex 13
  validation.two_phase_grain_interface_90 13
  output.paraview_reads_quickstart 13
  restart.fv_amr_implicit_2_ranks 11
  validation.psm_rotating_sphere 11
  restart.ibm_series 11
  validation.two_phase_laplace_2d 11
  validation.lbm_poiseuille_2d_pressure_order 11
  validation.ibm_lbm_vs_reference_moving 10
  restart.dpm_dispersion_series 10
  restart.fluid_walls 9
  restart.fv_amr_2_ranks 9
  restart.ibm_with_particles 9
  validation.ibm_ke_fv_vs_reference 9
  restart.fv_k_epsilon_2_ranks 9
  restart.fv_k_epsilon_intensity 3
  launcher.interrupt 9
  validation.two_phase_colour_mass 9
  validation.fv_ke_ranks_1_vs_2_channel 9
  validation.dpm_two_way_amr 9
  validation.dpm_two_way_amr_implicit 9
  validation.two_phase_grains_vs_reference 8
)
list(LENGTH coflow_test_costs n)
math(EXPR last "${n} - 1")
foreach(i RANGE 0 ${last} 2)
  math(EXPR j "${i} + 1")
  list(GET coflow_test_costs ${i} t)
  list(GET coflow_test_costs ${j} cost)
  if(TEST ${t})
    set_tests_properties(${t} PROPERTIES COST ${cost})
  else()
    message(WARNING "tests/test_costs.cmake: no test named ${t}")
  endif()
endforeach()
