# Scenarios at parameters away from their defaults: each fixed edge case keeps a test here.
set(scenes ${CMAKE_SOURCE_DIR}/scenarios)

# binary_impact: the spheres touch with the line of centres at the stated
# angle, so the peak force is (K m/2)^(1/2) v cos(angle) (0.00348 N at 80 deg,
# 0.00343 at n = 40); a grazing, slow impact does not spend its steps on the approach.
add_test(NAME params.binary_impact_angle80
  COMMAND granule run ${scenes}/binary_impact.lua -D angle=80 -o params_bi_angle80.h5 --quiet)
set_tests_properties(params.binary_impact_angle80 PROPERTIES PASS_REGULAR_EXPRESSION "max_normal_force=0\\.0034[3-8]")
add_test(NAME params.binary_impact_grazing
  COMMAND granule run ${scenes}/binary_impact.lua -D angle=89.999 -D velocity=1e-6 -o params_bi_grazing.h5 --quiet)
set_tests_properties(params.binary_impact_grazing PROPERTIES TIMEOUT 60
  PASS_REGULAR_EXPRESSION "angle=89\\.999 .*restitution=0\\.8[0-9]* stuck=false")
# Walton-Braun at small e: the latched overlap a_max (1 - e^2) clears at e v,
# which the time allowed covers; a tiny e (time step ~ e) is refused by name.
add_test(NAME params.binary_impact_low_restitution
  COMMAND granule run ${scenes}/binary_impact.lua -D restitution=0.01 -o params_bi_e001.h5 --quiet)
set_tests_properties(params.binary_impact_low_restitution PROPERTIES PASS_REGULAR_EXPRESSION "restitution=0\\.0100[0-9]* stuck=false")
add_test(NAME params.binary_impact_tiny_restitution
  COMMAND granule run ${scenes}/binary_impact.lua -D restitution=1e-6 -o params_bi_e1e-6.h5 --quiet)
set_tests_properties(params.binary_impact_tiny_restitution PROPERTIES TIMEOUT 60
  PASS_REGULAR_EXPRESSION "needs [0-9.e+]+ steps .*raise restitution \\(1e-06")
# binary_impact_map: the free line fit needs distinct velocities.
add_test(NAME params.binary_impact_map_repeated_velocity
  COMMAND granule run ${scenes}/binary_impact_map.lua -D angles=0 -D velocities=1,1 -o params_map_repeat.h5 --quiet)
set_tests_properties(params.binary_impact_map_repeated_velocity PROPERTIES PASS_REGULAR_EXPRESSION "velocities: 1 is given twice")
add_test(NAME params.binary_impact_tangential_ratio_zero
  COMMAND granule run ${scenes}/binary_impact.lua -D tangential_ratio=0 -o params_bi_tau0.h5 --quiet)
set_tests_properties(params.binary_impact_tangential_ratio_zero PROPERTIES
  PASS_REGULAR_EXPRESSION "-D tangential_ratio=0: 'tangential_ratio' must be > 0")

# drum_3d: a coarse mesh drum is filled inside its inscribed circle, so no bead
# starts outside the shell (one that did fell away and tilted the fit to 89 deg);
# the angle is what a rolling bed gives, of either turning sense, about 0
# without friction, and no angle at all from beads too few to fit a surface.
set(drum_short -D particles=300 -D duration=0.5)
add_test(NAME params.drum_3d_triangle
  COMMAND granule run ${scenes}/drum_3d.lua -D drum=mesh -D facets=3 -D particles=50 -D settle=0.2
          -D duration=0.3 -o params_drum_triangle.h5 --quiet)
set_tests_properties(params.drum_3d_triangle PROPERTIES
  PASS_REGULAR_EXPRESSION "dynamic angle of repose ([5-9]|[1-5][0-9])\\.[0-9] \\+-")
add_test(NAME params.drum_3d_rolling_angle
  COMMAND granule run ${scenes}/drum_3d.lua ${drum_short} -o params_drum.h5 --quiet)
set_tests_properties(params.drum_3d_rolling_angle PROPERTIES
  PASS_REGULAR_EXPRESSION "dynamic angle of repose ([5-9]|[1-5][0-9])\\.[0-9] \\+-")
add_test(NAME params.drum_3d_reversed
  COMMAND granule run ${scenes}/drum_3d.lua ${drum_short} -D rpm=-30 -o params_drum_reversed.h5 --quiet)
set_tests_properties(params.drum_3d_reversed PROPERTIES
  PASS_REGULAR_EXPRESSION "dynamic angle of repose ([5-9]|[1-5][0-9])\\.[0-9] \\+-")
add_test(NAME params.drum_3d_frictionless
  COMMAND granule run ${scenes}/drum_3d.lua ${drum_short} -D friction=0 -o params_drum_frictionless.h5 --quiet)
set_tests_properties(params.drum_3d_frictionless PROPERTIES
  PASS_REGULAR_EXPRESSION "dynamic angle of repose -?[0-4]\\.[0-9] \\+-[^\n]*\n(.*\n)?results written to")
add_test(NAME params.drum_3d_few_beads
  COMMAND granule run ${scenes}/drum_3d.lua -D particles=2 -D settle=0.2 -D duration=0.5 -o params_drum_few.h5 --quiet)
set_tests_properties(params.drum_3d_few_beads PROPERTIES
  PASS_REGULAR_EXPRESSION "no angle of repose \\(none of [0-9]+ samples .*particles=2 too few")

# tools/plot_pattern.py takes the tutorial's negative slab bound -1e-3 (argparse
# alone reads it as an option).
add_test(NAME params.plot_pattern_negative_slab
  COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tools/plot_pattern.py output_3d_test.h5 --view xz
          --slab -1e-3 1e-3 -o params_slab_test.png)
set_tests_properties(params.plot_pattern_negative_slab PROPERTIES FIXTURES_REQUIRED output_3d
  PASS_REGULAR_EXPRESSION "params_slab_test.png")

# shear_cell: the servo on the lid's mean force over its 20 steps holds a low
# pressure (the last step's force held 63 Pa for 100); the middle shear rate,
# one fit over the window, is in the walls' sense and reported, not asserted.
add_test(NAME params.shear_cell_low_pressure
  COMMAND granule run ${scenes}/shear_cell.lua -D pressure=100 -D duration=2 -o params_shear_100pa.h5 --quiet)
set_tests_properties(params.shear_cell_low_pressure PROPERTIES
  PASS_REGULAR_EXPRESSION "pressure (9[5-9]|10[0-5])(\\.[0-9])? Pa")
add_test(NAME params.shear_cell_long
  COMMAND granule run ${scenes}/shear_cell.lua -D particles=120 -D duration=2 -o params_shear_long.h5 --quiet)
set_tests_properties(params.shear_cell_long PROPERTIES
  PASS_REGULAR_EXPRESSION "mu_eff 0\\.[1-9][0-9]*, shear rate in the middle [0-9.]+ 1/s")

# hopper_mesh: geometry parameters that are not the STL's are refused by name.
add_test(NAME params.hopper_mesh_mismatch
  COMMAND granule run ${scenes}/hopper_mesh.lua -D file=hopper_test.stl -D half_angle=40 -o params_hopper.h5 --quiet)
set_tests_properties(params.hopper_mesh_mismatch PROPERTIES FIXTURES_REQUIRED hopper_stl
  PASS_REGULAR_EXPRESSION "is not the hopper of bin_radius=0\\.03 m, .*half_angle=40 deg")

# A tall frictionless column (6 mm box, 300 beads, e = 0.9) rings as a whole
# after it settles, passing near rest twice a period: calm at three checks in a
# row and wall forces averaged over 7 sqrt(d / g) give the weight on the floor.
# settle = 2 s: it settles near 1 s.
add_test(NAME params.packing_3d_ringing_column
  COMMAND granule run ${scenes}/packing_3d.lua -D friction=0 -D box=6e-3 -D particles=300
          -D restitution=0.9 -D settle=2 -o params_packing_column.h5 --quiet)
set_tests_properties(params.packing_3d_ringing_column PROPERTIES
  PASS_REGULAR_EXPRESSION "packing_3d: .*floor carries (99\\.[5-9]|100\\.[0-4]) %")
# A few beads fill and settle (the fill region is at least two diameters high)
# and are reported; too many for an overlapping fill are refused by name.
add_test(NAME params.packing_3d_one_bead
  COMMAND granule run ${scenes}/packing_3d.lua -D particles=1 -o params_packing_one.h5 --quiet)
set_tests_properties(params.packing_3d_one_bead PROPERTIES
  PASS_REGULAR_EXPRESSION "packing_3d: .*solid fraction 0\\.0[0-9]*, floor carries 100\\.0 %")
add_test(NAME params.shear_cell_one_bead
  COMMAND granule run ${scenes}/shear_cell.lua -D particles=1 -D duration=0.3 -o params_shear_one.h5 --quiet)
set_tests_properties(params.shear_cell_one_bead PROPERTIES
  PASS_REGULAR_EXPRESSION "too few samples .*raise particles \\(1\\)")
add_test(NAME params.tutorial_drum_too_many
  COMMAND granule run ${scenes}/tutorial_drum.lua -D particles=1000 -o params_tutorial_many.h5 --quiet)
set_tests_properties(params.tutorial_drum_too_many PROPERTIES
  PASS_REGULAR_EXPRESSION "-D particles=1000: 'particles' must be .*<= 300")
# The most the range allows runs; larger beads over 3/4 of the drum's area are refused.
add_test(NAME params.tutorial_drum_most
  COMMAND granule run ${scenes}/tutorial_drum.lua -D particles=300 -D settle=0.05 -D duration=0.01
          -o params_tutorial_most.h5 --quiet)
set_tests_properties(params.tutorial_drum_most PROPERTIES PASS_REGULAR_EXPRESSION "tutorial_drum: t = 0\\.0[0-9]+ s")
add_test(NAME params.tutorial_drum_too_large
  COMMAND granule run ${scenes}/tutorial_drum.lua -D particles=100 -D radius=2e-3 -o params_tutorial_large.h5 --quiet)
set_tests_properties(params.tutorial_drum_too_large PROPERTIES
  PASS_REGULAR_EXPRESSION "particles = 100 of radius 0.002 m cover 1.00 of the drum's area")

# "Calm" is not met before the beads, let go at rest, could have fallen: one
# bead dropped in the tutorial's drum is still falling at 0.08 s, and three
# spheres make a surface of too few bins for an angle.
add_test(NAME params.tutorial_drum_one_bead
  COMMAND granule run ${scenes}/tutorial_drum.lua -D particles=1 -D settle=0.1 -D duration=0.1
          -o params_tutorial_one.h5 --quiet)
set_tests_properties(params.tutorial_drum_one_bead PROPERTIES PASS_REGULAR_EXPRESSION "stage settle +t = 0\\.(09|1)")
add_test(NAME params.repose_rolling_three_fill
  COMMAND granule run ${scenes}/repose_rolling.lua -D particles=3 -D duration=0.3 -o params_repose_fill.h5 --quiet)
set_tests_properties(params.repose_rolling_three_fill PROPERTIES PASS_REGULAR_EXPRESSION "stage fill +t = 0\\.[1-9]")
add_test(NAME params.repose_rolling_three
  COMMAND granule run ${scenes}/repose_rolling.lua -D particles=3 -D duration=0.3 -o params_repose_three.h5 --quiet)
set_tests_properties(params.repose_rolling_three PROPERTIES
  PASS_REGULAR_EXPRESSION "no angle \\(the surface spans [0-2] bins? .*particles=3 too few")

# oblique_impact: an adhesive pair that stays in contact has stuck (e = 0).
add_test(NAME params.oblique_impact_stuck
  COMMAND granule run ${scenes}/oblique_impact.lua -D angles=0 -D surface_energies=0.2 -D speed=0.001
          -o params_oblique_stuck.h5 --quiet)
set_tests_properties(params.oblique_impact_stuck PROPERTIES PASS_REGULAR_EXPRESSION "\n0\\.2 0 0 -?[0-9.e+-]+ 0 [0-9]")

# silo_3d with spheres ten times the default's (4 cm, the orifice and silo 10
# times too, 3000 of them; a stiffer modulus keeps them from sinking into one
# another; settle and the window long enough for the bed's fall and steady
# flow at this size): the shutter drops away in proportion, so no sphere
# lands on it, and the flow keeps its ratio to Beverloo's law (about 0.9 at
# D / d = 7.5, as at the default size: docs/walls.md).
add_test(NAME params.silo_3d_large_spheres
  COMMAND granule run ${scenes}/silo_3d.lua -D diameter=0.04 -D orifice=0.3 -D silo_diameter=0.8
          -D particles=3000 -D settle=1.5 -D window_start=0.5 -D window_end=1.5 -D young=1e8
          -o params_silo_large.h5 --quiet)
set_tests_properties(params.silo_3d_large_spheres PROPERTIES TIMEOUT 120
  PASS_REGULAR_EXPRESSION "W / Beverloo = (0\\.[89]|1\\.[01])")
# Inconsistent parameters are refused by name before anything runs.
add_test(NAME params.silo_3d_window_reversed
  COMMAND granule run ${scenes}/silo_3d.lua -D window_start=0.3 -D window_end=0.1 -o params_silo_window.h5 --quiet)
set_tests_properties(params.silo_3d_window_reversed PROPERTIES TIMEOUT 30
  PASS_REGULAR_EXPRESSION "window_start=0\\.3 s and window_end=0\\.1 s: need 0 <= window_start < window_end")
add_test(NAME params.coating_hosts_without_collisions
  COMMAND granule run ${CMAKE_SOURCE_DIR}/tools/coating.lua -D hosts=100 --quiet)
set_tests_properties(params.coating_hosts_without_collisions PROPERTIES
  PASS_REGULAR_EXPRESSION "hosts=100 .*give -D collisions=FILE\\.csv")
add_test(NAME params.coating_deformation_packing_ratio
  COMMAND granule run ${scenes}/coating_deformation.lua -D packing_ratio=2 -o params_coating_packing.h5 --quiet)
set_tests_properties(params.coating_deformation_packing_ratio PROPERTIES
  PASS_REGULAR_EXPRESSION "-D packing_ratio=2: 'packing_ratio' must be > 0 and <= 1")
