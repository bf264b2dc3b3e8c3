#include "lua/api_docs.hpp"

#include <fmt/format.h>

#include <lua.hpp>

#include "contact/parameters.hpp"
#include "hooks/diagnostic.hpp"
#include "lua/lua_util.hpp"

namespace granule::lua {

namespace {

constexpr auto T = CallForm::table;
constexpr auto P = CallForm::positional;
constexpr auto V = CallForm::value;

// clang-format off
// One entry per exported name. Units are SI; "-" is dimensionless.
const std::vector<FunctionDoc> entries = {
// ---- globals ----
{"simulation", "global", T,
 "simulation { dimension = 2|3, time_step =, steps_per_contact =, skin =, record_contacts =, overlap_warning =, periodic = { axis =, origin =, length = } } -> sim",
 "Creates an empty simulation: add materials, contact laws, walls and particles, then run it.",
 {{"dimension", "integer", "", false, "2 (discs moving in x-y, spinning about z) or 3; default 3"},
  {"time_step", "number", "s", false, "fixed time step; 0 (default) = the Eq. 4.1 rule over the pairs in use"},
  {"steps_per_contact", "number", "-", false, "n of Eq. 4.1: steps per contact duration; default 40; refused if dt = t_c / n reaches the stability limit 1/omega (linear, Walton-Braun: n > pi; Hertz, Thornton: n > 16)"},
  {"skin", "number", "m", false, "neighbour-list skin; 0 (default) = half the median radius; refused above the scene's extent"},
  {"record_contacts", "boolean", "", false, "keep per-contact forces for sim:contacts(); default false"},
  {"overlap_warning", "number", "-", false, "warn once when two particles overlap by more than this fraction of the smaller radius, with the speed their contact would launch them at; default 0.1, in (0, 1]. Above 1 a pair passing through the other stops the run (one the scene placed so is pushed apart)"},
  {"threads", "integer", "", false, "threads for the force and integration loops; 0 (default) = OMP_NUM_THREADS, else 1; --threads N overrides; warned above twice the cores"},
  {"periodic", "table", "", false, "3D only: { axis = 'x'|'y'|'z', origin = m, length = m } wraps that axis"}},
 "{ dimension = 2 }", false, true},
{"parameters", "global", T,
 "parameters { name = default | { default =, unit =, doc = }, ... } -> read-only table",
 "Declares the scene's parameters (once per scene); -D name=value on the command line overrides a default.",
 {{"<name>", "any", "", false, "a number, string or boolean default, or { default =, unit = 'm/s', doc = '...' }"}},
 "{ speed = { default = 1, unit = 'm/s' } }", true},
{"help", "global", P, "help([x])",
 "Prints the documentation of a function (a name such as 'fill' or 'sim:fill', or the function itself); help() lists everything.",
 {{"1", "any", "", false, "a name, a function, sim (its methods) or granule (the library)"}},
 "'sim:fill'"},
{"api_reference", "global", P, "api_reference() -> { {name =, signature =, doc =, args = {...}, ...}, ... }",
 "The documentation table that help() prints, as Lua data.", {}, ""},
{"simulations", "global", P, "simulations() -> { sim, ... }",
 "The simulations created in this session, oldest first (the REPL binds the last one to `sim`).", {}, ""},
{"wall_time", "global", P, "wall_time() -> s",
 "Seconds of wall-clock time from an arbitrary origin, for timing runs (os.clock counts the CPU time of every thread).", {}, ""},
{"GRANULE_VERSION", "global", V, "GRANULE_VERSION", "The program's version, a string.", {}},
{"SCENE_PATH", "global", V, "SCENE_PATH", "The path of the scene file being run ('' in a REPL without one).", {}},

// ---- set-up ----
{"sim:material", "simulation", T,
 "sim:material { name =, density =, young =, poisson =, surface_energy = } -> name",
 "Declares a material that particles and walls are made of.",
 {{"name", "string", "", true, "how particles, walls and contact laws refer to it"},
  {"density", "number", "kg/m^3", false, "needed (> 0) for particles; walls may leave it 0"},
  {"young", "number", "Pa", false, "Young's modulus (Hertz and Thornton models)"},
  {"poisson", "number", "-", false, "Poisson's ratio, in (-1, 0.5]"},
  {"surface_energy", "number", "J/m^2", false, "surface energy (adhesive models)"}},
 "{ name = 'rubber', density = 1100 }"},
{"sim:contact", "simulation", T,
 "sim:contact { 'a', 'b', model = name, <model parameters> }",
 "Declares the contact law between materials a and b, once per pair: a second declaration (in either order) is refused naming both lines; sim:set_contact changes parameters. `granule models` lists the models and their parameters.",
 {{"1", "string", "", true, "first material"},
  {"2", "string", "", true, "second material (may equal the first)"},
  {"model", "string", "", true, "walton_braun | linear | hertz_mindlin | thornton_elastic | thornton_jkr"},
  {"<parameter>", "number", "", false, "the model's parameters, e.g. k_load [N/m], restitution, friction"}},
 "{ 'steel', 'steel', model = 'linear', k_normal = 1e4, restitution = 0.8, friction = 0.3 }", true},
{"sim:schedule", "simulation", T,
 "sim:schedule { target, constant = v | linear = { t0, v0, t1, v1 } | piecewise = { t1, v1, t2, v2, ... } | points = { { t1, v1 }, ... }, from =, to =, wall =, direction = }",
 "A value that follows simulated time, set in C++ before every step to its value at that step's time: linear between the points, held before the first and after the last; two points at one time are a jump. Saved in checkpoints (a restart must declare the same schedules).",
 {{"1", "string", "", true, "the target: 'central_strength' (m/s^2; after sim:central_field), 'wall_angular_velocity' (rad/s, a cylinder), 'wall_velocity' (m/s along `direction`, a plane), or a contact parameter of the from-to pair ('friction', 'surface_energy', ...)"},
  {"constant", "number", "", false, "a value held at all times"},
  {"linear", "list", "s, -", false, "{ t0, v0, t1, v1 }: v0 until t0, linear to v1 at t1 (> t0), then v1"},
  {"piecewise", "list", "s, -", false, "{ t1, v1, t2, v2, ... }: linear through the points, times non-decreasing"},
  {"points", "table", "s, -", false, "{ { t1, v1 }, { t2, v2 }, ... }: the same as a table of {time, value} pairs"},
  {"from", "string", "", false, "contact parameters: the first material of the pair"},
  {"to", "string", "", false, "contact parameters: the second material of the pair"},
  {"wall", "string", "", false, "wall targets: the wall's name"},
  {"direction", "vector", "-", false, "wall_velocity: the direction of the velocity (normalised)"}},
 "{ 'friction', from = 'glass', to = 'glass', linear = { 0, 0.3, 0.01, 0.5 } }"},
{"sim:set_contact", "simulation", P, "sim:set_contact('a', 'b', { <parameter> = value, ... })",
 "Changes some parameters of an existing contact law, e.g. between two stages of a run.",
 {{"1", "string", "", true, "first material"},
  {"2", "string", "", true, "second material"},
  {"3", "table", "", true, "the parameters to change, e.g. { friction = 0.25 }"}},
 "'glass', 'glass', { friction = 0.25 }"},
{"sim:contact_parameters", "simulation", P, "sim:contact_parameters('a', 'b') -> { model =, <parameter> = value, ... }",
 "The contact law between two materials with every parameter resolved (defaults filled in).",
 {{"1", "string", "", true, "first material"}, {"2", "string", "", true, "second material"}},
 "'glass', 'steel'"},
{"sim:materials", "simulation", P, "sim:materials() -> { { name =, density =, young =, poisson =, surface_energy = }, ... }",
 "The declared materials, in declaration order.", {}, ""},
{"sim:wall_plane", "simulation", T,
 "sim:wall_plane { name =, material =, point =, normal =, velocity = }",
 "Adds an infinite plane wall; particles live on the side the normal points to.",
 {{"name", "string", "", true, "the wall's name (unique)"},
  {"material", "string", "", true, "what the wall is made of"},
  {"point", "vector", "m", true, "a point on the plane"},
  {"normal", "vector", "-", true, "points towards the particles (normalised for you)"},
  {"velocity", "vector", "m/s", false, "translation velocity; default zero"}},
 "{ name = 'lid', point = { 0, 0.009 }, normal = { 0, -1 }, material = 'steel' }"},
{"sim:wall_cylinder", "simulation", T,
 "sim:wall_cylinder { name =, material =, center =, axis =, radius =, inside =, angular_velocity = }",
 "Adds an infinite cylinder wall (a circle in 2D), turning about its axis.",
 {{"name", "string", "", true, "the wall's name (unique)"},
  {"material", "string", "", true, "what the wall is made of"},
  {"center", "vector", "m", true, "a point on the axis"},
  {"axis", "vector", "-", false, "3D only: axis direction; default {0, 0, 1}"},
  {"radius", "number", "m", true, "cylinder radius"},
  {"inside", "boolean", "", false, "true (default): particles inside (a chamber); false: outside (a post)"},
  {"angular_velocity", "number", "rad/s", false, "right-handed about the axis; default 0"}},
 "{ name = 'post', center = { 0.005, 0 }, radius = 1e-3, inside = false, material = 'steel' }"},
{"sim:set_wall", "simulation", P, "sim:set_wall(name, { velocity = v | angular_velocity = w })",
 "Changes how a wall moves: a plane's velocity or a cylinder's angular velocity.",
 {{"1", "string", "", true, "wall name"},
  {"2", "table", "", true, "{ velocity = vector [m/s] } for a plane, { angular_velocity = number [rad/s] } for a cylinder"}},
 "'drum', { angular_velocity = 10 }"},
{"sim:wall", "simulation", P, "sim:wall(name) -> { name =, type =, force =, torque =, point | center =, ... }",
 "A wall's state: geometry, motion, and the force [N] and axial torque [N m] the particles exerted on it in the last step.",
 {{"1", "string", "", true, "wall name"}}, "'drum'"},
{"sim:walls", "simulation", P, "sim:walls() -> { name, ... }", "The names of the walls, in declaration order.", {}, ""},
{"sim:add_particle", "simulation", T,
 "sim:add_particle { position =, radius =, material =, velocity =, spin =, fixed = } -> id",
 "Adds one particle and returns its persistent id.",
 {{"position", "vector", "m", true, "centre"},
  {"radius", "number", "m", true, "> 0"},
  {"material", "string", "", true, "a declared material with density > 0"},
  {"velocity", "vector", "m/s", false, "default zero"},
  {"spin", "any", "rad/s", false, "2D: a number (about z); 3D: a vector; default zero"},
  {"fixed", "boolean", "", false, "immobile (infinite mass); default false"}},
 "{ position = { 0, 0.0085 }, radius = 5e-4, material = 'glass', velocity = { 0.1, 0 } }"},
{"sim:fill", "simulation", T,
 "sim:fill { region = { circle|sphere|box|cylinder = {...} }, count =, radius = | radii = | radius_min =, radius_max =, material =, seed =, max_speed =, max_attempts =, overlap = } -> { id, ... }",
 "Places `count` particles at random inside a region and the walls; they may overlap each other (as in dissertation 4.2.5) unless overlap = false, never fixed particles.",
 {{"region", "table", "", true, "circle = { center, radius } (2D), sphere = {...} (3D), box = { lo, hi }, cylinder = { center, radius, z_min, z_max } (3D)"},
  {"count", "integer", "", true, "number of particles; refused when their memory would exceed what the machine has available"},
  {"material", "string", "", true, "material of every particle"},
  {"radius", "number", "m", false, "one radius for all"},
  {"radii", "list", "m", false, "or radii drawn uniformly from this list"},
  {"radius_min", "number", "m", false, "or a radius uniform in [radius_min, radius_max]"},
  {"radius_max", "number", "m", false, "upper end of that range"},
  {"seed", "integer", "", false, "random seed; default 1"},
  {"max_speed", "number", "m/s", false, "random initial speeds up to this, zero net momentum; default 0"},
  {"max_attempts", "integer", "", false, "placement tries before giving up; default 2000 per particle"},
  {"overlap", "boolean", "", false, "false: no particle may overlap another; default true. Overlaps with a stiff law launch particles at tens of m/s in the first steps (warned, with the speed: overlap_warning of simulation {}); false is the gentle start"}},
 "{ region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = 'glass', seed = 2 }"},
{"sim:gravity", "simulation", P, "sim:gravity { gx, gy[, gz] }", "Sets a uniform gravitational acceleration.",
 {{"1", "vector", "m/s^2", true, "acceleration, e.g. { 0, -9.81 }"}}, "{ 0, -9.81 }"},
{"sim:central_field", "simulation", T, "sim:central_field { point =, strength = }",
 "Adds an acceleration of constant magnitude towards a point (a 'central field').",
 {{"point", "vector", "m", true, "the attracting point"},
  {"strength", "number", "m/s^2", true, "magnitude of the acceleration, >= 0"}},
 "{ point = { 0, 0 }, strength = 1 }"},
{"sim:set_central_strength", "simulation", P, "sim:set_central_strength(strength)",
 "Changes the central field's strength (e.g. a ramp in a callback).",
 {{"1", "number", "m/s^2", true, ">= 0"}}, "2"},
{"sim:central_strength", "simulation", P, "sim:central_strength() -> number",
 "The central field's strength [m/s^2] (0 without a field).", {}, ""},
{"sim:remove_central_field", "simulation", P, "sim:remove_central_field()", "Switches the central field off.", {}, ""},

// ---- particles ----
{"sim:particle", "simulation", P,
 "sim:particle(id) -> { id =, position =, velocity =, spin =, force =, radius =, mass =, material =, fixed = }",
 "One particle's state (SI units: m, m/s, rad/s, N, kg).", {{"1", "integer", "", true, "particle id"}}, "3"},
{"sim:particles", "simulation", P, "sim:particles() -> { id, ... }", "The ids of the particles present.", {}, ""},
{"sim:set_position", "simulation", P, "sim:set_position(id, { x, y[, z] })", "Moves a particle.",
 {{"1", "integer", "", true, "particle id"}, {"2", "vector", "m", true, "new centre"}}, "3, { 0, 0 }"},
{"sim:set_velocity", "simulation", P, "sim:set_velocity(id, { vx, vy[, vz] })", "Sets a (free) particle's velocity.",
 {{"1", "integer", "", true, "particle id"}, {"2", "vector", "m/s", true, "new velocity"}}, "3, { 0.1, 0 }"},
{"sim:set_spin", "simulation", P, "sim:set_spin(id, w)", "Sets a (free) particle's spin.",
 {{"1", "integer", "", true, "particle id"},
  {"2", "any", "rad/s", true, "2D: a number (about z); 3D: a vector"}}, "3, 5"},
{"sim:remove_particle", "simulation", P, "sim:remove_particle(id)", "Removes a particle; the other ids do not change.",
 {{"1", "integer", "", true, "particle id"}}, "3"},

// ---- running ----
{"sim:run", "simulation", T, "sim:run { duration = | steps =, stop_when =, check_every = } -> { steps =, time =, stopped = }",
 "Advances the simulation; shows a progress line on a terminal for long runs; Ctrl-C stops it at a step boundary.",
 {{"duration", "number", "s", false, "simulated time to advance (give this or steps)"},
  {"steps", "integer", "", false, "or a number of steps"},
  {"stop_when", "function", "", false, "function(sim) -> true ends the run early"},
  {"check_every", "integer", "", false, "steps between stop_when calls; default 100"}},
 "{ steps = 10 }"},
{"sim:every", "simulation", T, "sim:every { steps = n | time = t, function(sim) ... end, name = } -> hook id",
 "Calls a function every n steps or every t seconds of simulated time, during runs.",
 {{"1", "function", "", true, "function(sim)"},
  {"steps", "integer", "", false, "period in steps (> 0), or"},
  {"time", "number", "s", false, "period in simulated time (> 0)"},
  {"name", "string", "", false, "shown in the run header"}},
 "{ steps = 10, function(s) end }"},
{"sim:remove_hook", "simulation", P, "sim:remove_hook(id)", "Stops a callback that sim:every returned the id of.",
 {{"1", "integer", "", true, "hook id"}}, "sim:every { steps = 100, function(s) end }"},
{"sim:set", "simulation", T, "sim:set { skin =, time_step =, steps_per_contact =, threads =, pruning = }",
 "Changes numerical settings between runs; the next run re-checks the scene and rebuilds its neighbour lists.",
 {{"skin", "number", "m", false, "neighbour-list skin; 0 = automatic"},
  {"time_step", "number", "s", false, "fixed time step; 0 = the automatic rule"},
  {"steps_per_contact", "number", "-", false, "n of Eq. 4.1"},
  {"threads", "integer", "", false, "threads; 0 = OMP_NUM_THREADS, else 1"},
  {"pruning", "boolean", "", false, "prune the pair lists between rebuilds (default true): the contact loop then visits only candidates within a quarter of the skin of touching; the same results bit for bit"}},
 "{ skin = 1e-4 }"},
{"sim:prepare", "simulation", P, "sim:prepare()",
 "Checks the scene (laws for every pair, particles inside walls), chooses dt, builds neighbour lists; run does it for you.", {}, ""},

// ---- output ----
{"sim:output", "simulation", T, "sim:output { file =, snapshot_every =, series_every =, xdmf = } -> path",
 "Writes results to HDF5 (and an XDMF file beside it for ParaView); -o on the command line overrides `file`.",
 {{"file", "string", "", false, "default: -o, else <scene>.h5"},
  {"snapshot_every", "number", "s", false, "particle snapshots this often; 0 (default) = first and last"},
  {"series_every", "number", "s", false, "rows of /series this often; 0 (default) = every 100 steps"},
  {"xdmf", "boolean", "", false, "keep <file>.xmf (for ParaView) beside the HDF5 file; default true"}},
 "{ file = 'example_output.h5' }"},
{"sim:snapshot", "simulation", P, "sim:snapshot()", "Writes a particle snapshot now (needs sim:output).", {}, ""},
{"sim:series", "simulation", P, "sim:series(name, { column, ... })",
 "Declares a time series /<name> in the output with these columns.",
 {{"1", "string", "", true, "group name, a plain word"}, {"2", "list", "", true, "column names"}},
 "'extra', { 'time', 'energy' }"},
{"sim:append", "simulation", P, "sim:append(name, { value, ... })", "Appends one row to a declared series.",
 {{"1", "string", "", true, "series name"}, {"2", "list", "", true, "one finite number per column"}},
 "'probe', { 0, 1 }"},
{"sim:result", "simulation", T, "sim:result { name = value, ... }", "Records scalar results as attributes of /results; `granule sweep` gathers them into its summary table.",
 {{"<name>", "number", "", false, "a finite number"}}, "{ restitution = 0.85 }", true},
{"sim:close", "simulation", P, "sim:close()", "Writes the final snapshot and closes the output file.", {}, ""},
{"sim:checkpoint", "simulation", T, "sim:checkpoint { file =, every_steps =, every_seconds = }",
 "Writes checkpoints during runs (to a temporary file, then renamed); granule run SCENE --restart FILE continues bit-identically.",
 {{"file", "string", "", true, "checkpoint file (HDF5)"},
  {"every_steps", "integer", "", false, "every this many steps"},
  {"every_seconds", "number", "s", false, "or every this many seconds of wall-clock time"}},
 "{ file = 'example.chk.h5', every_steps = 1000 }"},
{"sim:save_checkpoint", "simulation", P, "sim:save_checkpoint(file)",
 "Writes a checkpoint now, between runs.", {{"1", "string", "", true, "checkpoint file (HDF5)"}},
 "'example.chk.h5'"},
{"sim:diagnostic", "simulation", P, "sim:diagnostic(name, { option = value, ... }) -> id",
 "Attaches a C++ diagnostic by name (`wall_force`, `zones`, `areas`, `contact_peaks`, `gap_profile`, `overlaps`: docs/mechanofusion.md; help('diagnostics') and help('<name>') list their options; how to add one: docs/architecture.md); a scene pays nothing for diagnostics it does not attach.",
 {{"1", "string", "", true, "diagnostic name: 'wall_force', 'zones', 'areas', 'contact_peaks', 'gap_profile', 'overlaps' (docs/mechanofusion.md)"},
  {"2", "table", "", false, "its options; nested tables become dotted names"}},
 "'wall_force', { wall = 'drum' }"},
{"sim:diagnostic_results", "simulation", P, "sim:diagnostic_results(id) -> { name = value, array = { ... }, ... }",
 "A diagnostic's scalar results and arrays so far.", {{"1", "integer", "", true, "id from sim:diagnostic"}},
 "sim:diagnostic('wall_force', { wall = 'drum' })"},
{"sim:remove_diagnostic", "simulation", P, "sim:remove_diagnostic(id)",
 "Detaches a diagnostic (its partly filled window is written first).", {{"1", "integer", "", true, "id from sim:diagnostic"}},
 "sim:diagnostic('wall_force', { wall = 'drum' })"},
{"sim:load_particles", "simulation", T,
 "sim:load_particles { file =, snapshot =, material_map =, offset =, velocity =, histories = } -> { id, ... }, histories",
 "Adds the particles of a saved snapshot (an agglomerate prepared once, reused by many tests), with the contact histories saved at its step.",
 {{"file", "string", "", true, "HDF5 file written by sim:output"},
  {"snapshot", "integer", "", false, "snapshot index; -1 (default) = the last"},
  {"material_map", "table", "", false, "{ saved_name = 'current_name' }"},
  {"offset", "vector", "m", false, "added to every position"},
  {"velocity", "vector", "m/s", false, "added to every velocity"},
  {"histories", "boolean", "", false, "restore the saved contact histories; default: where the file has them for this snapshot"}},
 "{ file = 'agglomerate.h5', offset = { 0.02, 0 } }"},
{"sim:save_contact_histories", "simulation", T, "sim:save_contact_histories { file =, particles = | material = } -> count",
 "Writes the contact histories among the particles into a closed output file, for sim:load_particles.",
 {{"file", "string", "", true, "the run's output, after sim:close()"},
  {"particles", "list", "", false, "only these ids"}, {"material", "string", "", false, "or only this material"}},
 "{ file = 'agglomerate.h5', material = 'glass' }"},
{"sim:bonds", "simulation", T, "sim:bonds { particles = {ids} | material = } -> { {a, b}, ... }",
 "The contact graph: pairs of particle ids in contact (needs record_contacts).",
 {{"particles", "list", "", false, "only these ids"}, {"material", "string", "", false, "or only this material"}},
 "{ material = 'glass' }", false, true},
{"sim:fragments", "simulation", T, "sim:fragments { particles = | material = } -> { count =, labels =, masses =, members = }",
 "Connected clusters of the contact graph (dissertation 7.4).",
 {{"particles", "list", "", false, "only these ids"}, {"material", "string", "", false, "or only this material"}},
 "{ material = 'glass' }", false, true},
{"sim:breakage", "simulation", T,
 "sim:breakage { initial_bonds =, particles = | material =, initial_mass =, initial_count =, large =, debris =, fines =, labels =, graph = }",
 "Damage and debris ratios and fragment classes against the initial bonds (dissertation 7.4-7.7).",
 {{"initial_bonds", "table", "", true, "sim:bonds {...} at the start"},
  {"particles", "list", "", false, "only these ids"}, {"material", "string", "", false, "or only this material"},
  {"initial_mass", "number", "kg", false, "default: the mass of the particles now"},
  {"initial_count", "integer", "", false, "primaries before the test, for the classes by size; default: those selected"},
  {"large", "number", "-", false, "mass fraction above which a fragment is large; default 0.1"},
  {"debris", "number", "-", false, "below which it is debris; default 0.025"},
  {"fines", "number", "-", false, "below which it is fines; default 0.002"},
  {"labels", "boolean", "", false, "also return each particle's fragment label"},
  {"graph", "string", "", false, "'contacts' (default) or 'surviving_bonds'"}},
 "{ initial_bonds = sim:bonds {} }"},
{"sim:scale_velocities", "simulation", T, "sim:scale_velocities { factor =, spin_factor =, particles = | material = }",
 "Multiplies velocities (and spins) by a factor: the damping of a preparation protocol.",
 {{"factor", "number", "-", true, "velocity factor"}, {"spin_factor", "number", "-", false, "spin factor; default factor"},
  {"particles", "list", "", false, "only these ids"}, {"material", "string", "", false, "or only this material"}},
 "{ factor = 1 }"},
{"sim:picture", "simulation", T,
 "sim:picture { file =, width =, height =, color_by =, range = { min, max }, view = { lo =, hi = }, walls =, legend = } -> file",
 "Draws the particles (3D: projected on x-y) and walls to a PNG or SVG file, without Python.",
 {{"file", "string", "", true, "ends in .png or .svg"},
  {"width", "integer", "", false, "pixels, 16..8192; default 800"},
  {"height", "integer", "", false, "pixels; default from the view's aspect ratio"},
  {"color_by", "string", "", false, "speed (default) | material | fixed | radius | spin"},
  {"range", "list", "", false, "{ min, max } of the colour scale, in the unit of color_by"},
  {"view", "table", "m", false, "{ lo = { x, y }, hi = { x, y } }; default: particles and walls"},
  {"walls", "boolean", "", false, "draw the walls; default true"},
  {"legend", "boolean", "", false, "draw time and colour scale; default true"}},
 "{ file = 'example_picture.svg', width = 200 }"},

// ---- queries ----
{"sim:stats", "simulation", P,
 "sim:stats() -> { time =, step =, particles =, kinetic_energy =, kinetic_energy_translational =, kinetic_energy_rotational =, momentum =, angular_momentum_z =, contacts_particle =, contacts_batched =, contacts_wall =, max_overlap_ratio =, candidate_pairs =, list_rebuilds =, thread_rebalances =, pair_list_prunes =, pair_candidates_visited = }",
 "Global quantities now (J, kg m/s, kg m^2/s); contacts_batched: of contacts_particle, those a batched (vectorised) contact kernel computed (3D pairs of a law that has one: linear), candidate_pairs: neighbour-list entries within the skin, list_rebuilds: rebuilds so far, thread_rebalances: times the threads' shares of the pair contacts were moved to even out their work, pair_list_prunes: times a pair list was pruned (sim:set pruning), pair_candidates_visited: pair candidates the last step's contact loop looked at (fewer than the pair candidates while pruned lists are in use).", {}, ""},
{"sim:contacts", "simulation", P,
 "sim:contacts() -> { { a =, b = | wall =, model =, overlap =, normal_force =, tangential_force =, normal = }, ... }",
 "The contacts of the last step (needs record_contacts = true).", {}, ""},
{"sim:time", "simulation", P, "sim:time() -> number", "Simulated time [s].", {}, ""},
{"sim:step_count", "simulation", P, "sim:step_count() -> integer", "Steps taken so far.", {}, ""},
{"sim:time_step", "simulation", P, "sim:time_step() -> number", "The time step [s] (chosen now if automatic).", {}, ""},
{"sim:time_step_rule", "simulation", P, "sim:time_step_rule() -> { rule =, stability_limit =, governing_pair = }",
 "What the time step rule gives [s], the largest time step accepted (1/omega, half leap-frog's limit) [s], and which pair governs.", {}, ""},
{"sim:describe", "simulation", P, "sim:describe() -> string",
 "What this scene simulates: models in use, walls, fields, hooks (the run header).", {}, ""},
{"sim:dimension", "simulation", P, "sim:dimension() -> 2|3", "The dimension of the simulation.", {}, ""},
{"sim:timings", "simulation", P, "sim:timings() -> { neighbor =, force =, diagnostics =, integrate =, hooks =, scatter =, walls =, pair_wait = }",
 "Wall-clock seconds spent in each stage of the step so far (scatter: the part of force, with more than one thread, that keeps each particle's sum in slot order: marking the particles two threads share, adding their deferred forces, summing the reactions on the walls; walls: the part of force spent on particle-wall contacts; pair_wait: with more than one thread, the seconds the threads of the particle-pair loop waited for one another at its barrier, summed over the threads: how unevenly they finished).", {}, ""},

// ---- the granule library (lua/granule/init.lua) ----
{"granule.pi", "library", V, "granule.pi", "The number pi, 3.14159...", {}},
{"granule.rpm", "library", P, "granule.rpm(revolutions_per_minute) -> rad/s",
 "Angular velocity from revolutions per minute.", {{"1", "number", "1/min", true, "speed"}}, "2000"},
{"granule.stiffness_from_young", "library", P, "granule.stiffness_from_young(young, radius) -> N/m",
 "Eq. 4.2: K_N = 0.01 pi E r, which keeps the deformation under 1 % of the diameter.",
 {{"1", "number", "Pa", true, "Young's modulus"}, {"2", "number", "m", true, "particle radius"}}, "1e9, 1e-3"},
{"granule.sphere_mass", "library", P, "granule.sphere_mass(radius, density) -> kg", "Sphere mass 4/3 pi r^3 rho.",
 {{"1", "number", "m", true, "radius"}, {"2", "number", "kg/m^3", true, "density"}}, "1e-3, 2500"},
{"granule.walton_braun_time_step", "library", P,
 "granule.walton_braun_time_step(mass, k_load, restitution[, steps_per_contact]) -> s",
 "Eq. 4.1: dt = pi e sqrt(m / (2 K)) / n for two equal spheres of mass m.",
 {{"1", "number", "kg", true, "particle mass"}, {"2", "number", "N/m", true, "loading stiffness"},
  {"3", "number", "-", true, "restitution"}, {"4", "number", "-", false, "n; default 40"}},
 "1e-6, 2e4, 0.85"},
{"granule.particle_row", "library", P, "granule.particle_row(start, direction, count, radius) -> { position, ... }",
 "Centres of `count` touching spheres in a straight row from `start` along `direction`.",
 {{"1", "vector", "m", true, "first centre"}, {"2", "vector", "-", true, "direction (any length)"},
  {"3", "integer", "", true, "how many"}, {"4", "number", "m", true, "radius"}},
 "{ 0, 0 }, { 1, 0 }, 3, 1e-3"},
{"granule.summary_line", "library", P, "granule.summary_line(values, order) -> string",
 "One line 'key=value key=value ...' with the keys in the given order.",
 {{"1", "table", "", true, "values by key"}, {"2", "list", "", true, "keys in order"}},
 "{ a = 1, b = 'x' }, { 'a', 'b' }"},
{"granule.stage", "library", P,
 "granule.stage(sim, { name =, duration = | steps =, stop_when =, check_every =, quiet = }) -> run result",
 "Runs one stage of a protocol and reports on stderr how it ended.",
 {{"1", "any", "", true, "the simulation"},
  {"2", "table", "", true, "name, duration [s] or steps, stop_when, check_every, quiet"}},
 "sim, { name = 'settle', steps = 10, quiet = true }"},
{"granule.vec.add", "library", P, "granule.vec.add(a, b) -> vector", "a + b.",
 {{"1", "vector", "", true, "a"}, {"2", "vector", "", true, "b"}}, "{ 1, 2 }, { 3, 4 }"},
{"granule.vec.sub", "library", P, "granule.vec.sub(a, b) -> vector", "a - b.",
 {{"1", "vector", "", true, "a"}, {"2", "vector", "", true, "b"}}, "{ 1, 2 }, { 3, 4 }"},
{"granule.vec.scale", "library", P, "granule.vec.scale(a, s) -> vector", "s a.",
 {{"1", "vector", "", true, "a"}, {"2", "number", "", true, "s"}}, "{ 1, 2 }, 2"},
{"granule.vec.dot", "library", P, "granule.vec.dot(a, b) -> number", "a . b.",
 {{"1", "vector", "", true, "a"}, {"2", "vector", "", true, "b"}}, "{ 1, 2 }, { 3, 4 }"},
{"granule.vec.norm", "library", P, "granule.vec.norm(a) -> number", "|a|.", {{"1", "vector", "", true, "a"}}, "{ 3, 4 }"},
{"granule.vec.unit", "library", P, "granule.vec.unit(a) -> vector", "a / |a| (a must not be zero).",
 {{"1", "vector", "", true, "a"}}, "{ 3, 4 }"},
{"granule.vec.polar", "library", P, "granule.vec.polar(angle[, length]) -> { x, y }",
 "The 2D vector at `angle` from +x with length `length` (default 1).",
 {{"1", "number", "rad", true, "angle from +x"}, {"2", "number", "", false, "length; default 1"}}, "0.5, 2"},
};
// clang-format on

std::string call_line(const FunctionDoc& d) {
  if (d.form == CallForm::value || !*d.example) return "";
  std::string name = d.name;
  if (d.form == CallForm::table) return name + " " + d.example;
  return name + "(" + d.example + ")";
}

std::string arg_type(const ArgDoc& a) {
  return *a.unit ? fmt::format("{} [{}]", a.type, a.unit) : a.type;
}

const char* section_title(const std::string& section) {
  if (section == "global") return "Globals";
  if (section == "simulation") return "Simulation methods";
  return "The granule library (`local granule = require \"granule\"`)";
}

}  // namespace

const std::vector<FunctionDoc>& api_docs() {
  return entries;
}

const FunctionDoc* find_doc(const std::string& name) {
  for (const auto& d : entries)
    if (name == d.name) return &d;
  // "fill" or "sim.fill" for "sim:fill"; "rpm" or "vec.add" for the library.
  std::string dotted = name;
  for (auto& c : dotted)
    if (c == ':') c = '.';
  const FunctionDoc* found = nullptr;
  for (const auto& d : entries) {
    std::string full = d.name;
    for (auto& c : full)
      if (c == ':') c = '.';
    if (full == dotted || (full.size() > dotted.size() &&
                           full.compare(full.size() - dotted.size(), dotted.size(), dotted) == 0 &&
                           full[full.size() - dotted.size() - 1] == '.')) {
      if (found) return nullptr;  // ambiguous
      found = &d;
    }
  }
  return found;
}

std::string nearest_doc_name(const std::string& name) {
  std::vector<std::string> names;
  for (const auto& d : entries) {
    names.emplace_back(d.name);
    std::string s = d.name;
    auto cut = s.find_last_of(".:");
    if (cut != std::string::npos) names.push_back(s.substr(cut + 1));
  }
  return nearest_name(name, names);
}

std::string format_help(const FunctionDoc& d) {
  std::string out = fmt::format("{}\n  {}\n", d.signature, d.doc);
  std::size_t width = 0;
  for (const auto& a : d.args) width = std::max(width, std::string(a.name).size());
  for (const auto& a : d.args) {
    bool positional = a.name[0] >= '0' && a.name[0] <= '9';
    std::string name = positional ? fmt::format("arg {}", a.name) : a.name;
    out += fmt::format("    {:<{}}  {:<22} {:<8} {}\n", name, width + 4, arg_type(a),
                       a.required ? "required" : "", a.doc);
  }
  if (d.open_keys) out += "    (other keys: see above)\n";
  std::string example = call_line(d);
  if (!example.empty()) out += "  example: " + example + "\n";
  return out;
}

std::string format_overview() {
  std::string out;
  std::string section;
  for (const auto& d : entries) {
    if (section != d.section) {
      section = d.section;
      out += fmt::format("{}{}:\n", out.empty() ? "" : "\n", section_title(section));
    }
    out += fmt::format("  {:<32} {}\n", d.name, d.doc);
  }
  out += "\nhelp('name') or help(function) for the arguments and an example.\n";
  return out;
}

std::string api_markdown() {
  std::string out =
      "# Lua API reference\n\n"
      "Generated by `build/granule api --markdown` from the one documentation table\n"
      "(`src/lua/api_docs.cpp`) that also drives `help()` in the REPL, the arity check of\n"
      "every binding and the fuzz test; `ctest -R docs.lua_api_up_to_date` fails when\n"
      "this page and the table differ. Units are SI; `-` means dimensionless. A\n"
      "`vector` is `{x, y}` in 2D and `{x, y, z}` in 3D.\n\n"
      "The examples run in this scene (the fuzz test runs every one of them):\n\n"
      "```lua\n"
      "local sim = simulation { dimension = 2, record_contacts = true }\n"
      "sim:material { name = \"glass\", density = 2500 }\n"
      "sim:material { name = \"steel\", density = 7800 }\n"
      "sim:contact { \"glass\", \"glass\", model = \"walton_braun\", k_load = 1e4, restitution = "
      "0.9, friction = 0.3 }\n"
      "sim:contact { \"glass\", \"steel\", model = \"walton_braun\", k_load = 1e4, restitution = "
      "0.9, friction = 0.5 }\n"
      "sim:wall_cylinder { name = \"drum\", center = { 0, 0 }, radius = 0.01, material = "
      "\"steel\" }\n"
      "sim:wall_plane { name = \"floor\", point = { 0, -0.009 }, normal = { 0, 1 }, material = "
      "\"steel\" }\n"
      "sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 20, "
      "radius = 5e-4,\n"
      "           material = \"glass\", seed = 1 }\n"
      "sim:output { file = \"fixture.h5\" }\n"
      "sim:series(\"probe\", { \"time\", \"value\" })\n"
      "```\n";
  std::string section;
  for (const auto& d : entries) {
    if (section != d.section) {
      section = d.section;
      out += fmt::format("\n## {}\n", section_title(section));
    }
    out += fmt::format("\n### `{}`\n\n```lua\n{}\n```\n\n{}\n", d.name, d.signature, d.doc);
    if (!d.args.empty()) {
      out += "\n| argument | type | unit | required | meaning |\n|---|---|---|---|---|\n";
      for (const auto& a : d.args) {
        bool positional = a.name[0] >= '0' && a.name[0] <= '9';
        std::string name = positional ? fmt::format("{} (position)", a.name) : a.name;
        std::string doc = a.doc;
        for (std::size_t p = doc.find('|'); p != std::string::npos; p = doc.find('|', p + 2))
          doc.replace(p, 1, "\\|");
        out += fmt::format("| `{}` | {} | {} | {} | {} |\n", name, a.type, *a.unit ? a.unit : "",
                           a.required ? "yes" : "", doc);
      }
    }
    if (d.open_keys) out += "\nOther keys are accepted as described above.\n";
    std::string example = call_line(d);
    if (!example.empty()) out += fmt::format("\nExample: `{}`\n", example);
  }
  return out + diagnostics_help("diagnostics", true);  // src/hooks/registry.cpp
}

namespace {

bool is_method(const FunctionDoc& d) {
  return std::string(d.name).rfind("sim:", 0) == 0;
}

// Runs before the binding: no C++ object with a destructor is alive in this
// frame, so raising the Lua error (a longjmp) here is safe.
int checked_call(lua_State* L) {
  const auto* d = static_cast<const FunctionDoc*>(lua_touserdata(L, lua_upvalueindex(1)));
  auto f = lua_tocfunction(L, lua_upvalueindex(2));
  const bool method = is_method(*d);
  int given = lua_gettop(L);
  if (method) {
    if (given == 0 || !luaL_testudata(L, 1, "granule.Simulation"))
      return script_error(L, "%s: call it with a colon, as %s(...)", d->name, d->name);
    --given;
  }
  int most = 0, least = 0;
  if (d->form == CallForm::table) {
    most = 1;
    least = d->table_optional ? 0 : 1;
  } else {
    for (const auto& a : d->args) {
      ++most;
      if (a.required) least = most;
    }
  }
  if (given < least || given > most) {
    if (d->form == CallForm::table)
      return script_error(L, "%s expects one table { ... }, got %d arguments (usage: %s)", d->name,
                          given, d->signature);
    if (least == most)
      return script_error(L, "%s expects %d argument%s, got %d (usage: %s)", d->name, least,
                          least == 1 ? "" : "s", given, d->signature);
    return script_error(L, "%s expects %d to %d arguments, got %d (usage: %s)", d->name, least,
                        most, given, d->signature);
  }
  return f(L);
}

// Follows a dotted/colon name to its value in this state; pushes it (or nil).
void push_named(lua_State* L, const std::string& name) {
  if (name.rfind("sim:", 0) == 0) {
    luaL_getmetatable(L, "granule.Simulation");
    if (lua_istable(L, -1)) {
      lua_getfield(L, -1, "__index");
      lua_remove(L, -2);
      if (lua_istable(L, -1)) {
        lua_getfield(L, -1, name.substr(4).c_str());
        lua_remove(L, -2);
        return;
      }
    }
    lua_pop(L, 1);
    lua_pushnil(L);
    return;
  }
  if (name.rfind("granule.", 0) == 0) {
    lua_getfield(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    lua_getfield(L, -1, "granule");
    lua_remove(L, -2);
    std::size_t pos = 8;
    while (lua_istable(L, -1)) {
      std::size_t dot = name.find('.', pos);
      std::string key = name.substr(pos, dot == std::string::npos ? std::string::npos : dot - pos);
      lua_pushstring(L, key.c_str());
      lua_rawget(L, -2);
      lua_remove(L, -2);
      if (dot == std::string::npos) return;
      pos = dot + 1;
    }
    lua_pop(L, 1);
    lua_pushnil(L);
    return;
  }
  lua_pushglobaltable(L);
  lua_pushstring(L, name.c_str());
  lua_rawget(L, -2);
  lua_remove(L, -2);
}

// help(x): x a name, a function, a simulation (its methods) or the granule table.
int l_help(lua_State* L) {
  return protect(L, [](lua_State* L) {
    std::string text;
    if (lua_isnoneornil(L, 1)) {
      text = format_overview();
    } else if (lua_type(L, 1) == LUA_TSTRING) {
      std::string name = lua_tostring(L, 1);
      const FunctionDoc* d = find_doc(name);
      const std::string diagnostic = diagnostics_help(name, false);  // src/hooks/registry.cpp
      if (!d && !diagnostic.empty()) {
        text = diagnostic;
      } else if (!d) {
        std::string hint = nearest_doc_name(name);
        throw std::runtime_error(
            fmt::format("help: nothing is called '{}'{}; help() lists every name", name,
                        hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint)));
      } else {
        text = format_help(*d) + diagnostic;
      }
    } else if (luaL_testudata(L, 1, "granule.Simulation")) {
      for (const auto& d : entries)
        if (is_method(d)) text += fmt::format("  {:<28} {}\n", d.name, d.doc);
    } else {
      for (const auto& d : entries) {
        push_named(L, d.name);
        bool same = !lua_isnil(L, -1) && lua_rawequal(L, -1, 1);
        lua_pop(L, 1);
        if (same) {
          text = format_help(d);
          break;
        }
      }
      if (text.empty()) {
        lua_getfield(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
        lua_getfield(L, -1, "granule");
        bool library = lua_rawequal(L, -1, 1);
        lua_pop(L, 2);
        if (library) {
          for (const auto& d : entries)
            if (std::string(d.section) == "library")
              text += fmt::format("  {:<34} {}\n", d.name, d.doc);
        }
      }
      if (text.empty())
        throw std::runtime_error(
            fmt::format("help: no documentation for this {} value; try help() or help('name')",
                        type_name(L, 1)));
    }
    std::fputs(text.c_str(), stdout);
    std::fflush(stdout);
    return 0;
  });
}

int l_api_reference(lua_State* L) {
  return protect(L, [](lua_State* L) {
    lua_createtable(L, static_cast<int>(entries.size()), 0);
    int k = 0;
    auto set = [L](const char* key, const char* value) {
      lua_pushstring(L, value);
      lua_setfield(L, -2, key);
    };
    for (const auto& d : entries) {
      lua_newtable(L);
      set("name", d.name);
      set("section", d.section);
      set("form", d.form == CallForm::table        ? "table"
                  : d.form == CallForm::positional ? "positional"
                                                   : "value");
      set("signature", d.signature);
      set("doc", d.doc);
      set("example", d.example);
      lua_pushboolean(L, d.open_keys);
      lua_setfield(L, -2, "open_keys");
      lua_pushboolean(L, d.table_optional);
      lua_setfield(L, -2, "table_optional");
      lua_createtable(L, static_cast<int>(d.args.size()), 0);
      int j = 0;
      for (const auto& a : d.args) {
        lua_newtable(L);
        set("name", a.name);
        set("type", a.type);
        set("unit", a.unit);
        set("doc", a.doc);
        lua_pushboolean(L, a.required);
        lua_setfield(L, -2, "required");
        lua_rawseti(L, -2, ++j);
      }
      lua_setfield(L, -2, "args");
      lua_rawseti(L, -2, ++k);
    }
    return 1;
  });
}

}  // namespace

void push_checked(lua_State* L, const FunctionDoc& doc, int (*f)(lua_State*)) {
  lua_pushlightuserdata(L, const_cast<FunctionDoc*>(&doc));
  lua_pushcfunction(L, f);
  lua_pushcclosure(L, checked_call, 2);
}

void open_help(lua_State* L) {
  push_checked(L, *find_doc("help"), l_help);
  lua_setglobal(L, "help");
  push_checked(L, *find_doc("api_reference"), l_api_reference);
  lua_setglobal(L, "api_reference");
}

}  // namespace granule::lua
