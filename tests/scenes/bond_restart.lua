-- Parallel bonds across a checkpoint/restart: a pile settles in a turning
-- drum, its touching pairs are bonded, and the drum tumbles it so that bonds
-- break, checkpointing every `checkpoint_every` steps. Restarted from its last
-- checkpoint it prints the same lines and ends in the same state.
local p = parameters {
  checkpoint = { default = "bond_restart.chk.h5" },
  checkpoint_every = { default = 2000 },
}
local sim = simulation { dimension = 2 }
sim:material { name = "powder", density = 1200 }
sim:material { name = "steel", density = 7800 }
sim:contact { "powder", "powder", model = "linear", k_normal = 2e3, restitution = 0.5, friction = 0.3 }
sim:contact { "powder", "steel", model = "linear", k_normal = 2e3, restitution = 0.5, friction = 0.5 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 6e-3, angular_velocity = 0, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 6e-3 } }, count = 200, radius = 0.3e-3,
           material = "powder", seed = 3, overlap = false }
sim:gravity { 0, -9.81 }
sim:output { snapshot_every = 2e-3 }
sim:checkpoint { file = p.checkpoint, every_steps = p.checkpoint_every }
sim:run { duration = 0.05 }
local made = sim:bond { normal_stiffness = 2e9, shear_stiffness = 1e9, tensile_strength = 2e3,
                        shear_strength = 2e3 }
sim:set_wall("drum", { angular_velocity = 60 })
sim:run { steps = 9000 }
local c = sim:bond_counts()
local x = sim:particle(0).position
print(string.format("bond-restart step=%d made=%d intact=%d broken=%d x0=%.17g y0=%.17g",
  sim:step_count(), made, c.intact, c.broken, x[1], x[2]))
