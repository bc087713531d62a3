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
