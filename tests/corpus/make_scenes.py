#!/usr/bin/python3
"""Writes tests/corpus/scenes/*.lua: small scenes, each wrong in one way.

Every scene is a copy of one of two tiny valid scenes (2D: five discs in a
drum; 3D: five spheres in a box) with one line changed, removed or added.
The changed line ends in the comment `-- <- wrong`; in a case's `expect`
regular expression `{at}` stands for `<scene>.lua:<that line>`, so the
message must name the scene file and the line the mistake is on (`{line}`
is the line's number alone).

    /usr/bin/python3 tests/corpus/make_scenes.py     # rewrites the scenes

The output is committed beside this script; run it again after changing a
case and commit both.
"""
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "scenes")
MARK = "-- <- wrong"

BASE2 = [
    ("sim", 'local sim = simulation { dimension = 2 }'),
    ("material", 'sim:material { name = "glass", density = 2500 }'),
    ("wall_material", 'sim:material { name = "steel", density = 0 }'),
    ("contact", 'sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }'),
    ("wall_contact", 'sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }'),
    ("wall", 'sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }'),
    ("fill", 'sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }'),
    ("output", 'sim:output {}'),
    ("run", 'sim:run { steps = 10 }'),
]

BASE3 = [
    ("sim", 'local sim = simulation { dimension = 3 }'),
    ("material", 'sim:material { name = "glass", density = 2500, young = 1e8, poisson = 0.3, surface_energy = 0.05 }'),
    ("wall_material", 'sim:material { name = "steel", density = 0, young = 2e8, poisson = 0.3, surface_energy = 0.05 }'),
    ("contact", 'sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.8, friction = 0.3 }'),
    ("wall_contact", 'sim:contact { "glass", "steel", model = "hertz_mindlin", restitution = 0.8, friction = 0.3 }'),
    ("wall", 'sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "steel" }'),
    ("fill", 'sim:fill { region = { box = { lo = { -0.002, -0.002, 0.001 }, hi = { 0.002, 0.002, 0.004 } } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }'),
    ("output", 'sim:output {}'),
    ("run", 'sim:run { steps = 10 }'),
]

CASES = []


def case(name, what, expect, replace=None, before=None, after=None, drop=(), args=None, base=BASE2):
    """replace: {key: line}; before/after: {key: [lines]} added around a base line;
    drop: base lines left out. The line carrying MARK is the one {at} points to."""
    CASES.append(dict(name=name, what=what, expect=expect, replace=replace or {}, before=before or {},
                      after=after or {}, drop=set(drop), args=args, base=base))


def wrong(line):
    return line + "  " + MARK


def build(c):
    lines = []
    for key, text in c["base"]:
        lines += c["before"].get(key, [])
        if key not in c["drop"]:
            lines.append(c["replace"].get(key, text))
        lines += c["after"].get(key, [])
    header = ["-- " + c["what"], "-- expect: " + c["expect"]]
    if c["args"]:
        header.append("-- args: " + c["args"])
    body = header + lines
    at = None
    for number, line in enumerate(body, 1):
        if line.endswith(MARK):
            at = number
            break
    expect = c["expect"]
    if "{at}" in expect:
        if at is None:
            sys.exit(f"{c['name']}: expect has {{at}} but no line is marked")
        expect = expect.replace("{at}", re.escape(c["name"] + ".lua") + ":" + str(at) + r"\b")
    if "{line}" in expect:
        expect = expect.replace("{line}", str(at))
    body[1] = "-- expect: " + expect
    re.compile(expect)
    return "\n".join(body) + "\n"


# ---------------------------------------------------------------------------
# Lua syntax errors
# ---------------------------------------------------------------------------
case("syntax_unclosed_brace", "syntax error: a table constructor never closed",
     r"syntax_unclosed_brace\.lua:\d+:.*'}' expected \(to close '\{' at line {line}\)", replace={"output": wrong("sim:output {")})
case("syntax_missing_end", "syntax error: a function without its 'end'",
     r"syntax_missing_end\.lua:\d+:.*'end' expected",
     after={"output": [wrong("local function f() return 1")]})
case("syntax_unclosed_string", "syntax error: a string never closed",
     r"{at}.*unfinished string", replace={"material": wrong('sim:material { name = "glass, density = 2500 }')})
case("syntax_bad_character", "syntax error: a character Lua does not know",
     r"{at}.*unexpected symbol", after={"output": [wrong("local x = 1 @ 2")]})
case("syntax_assign_in_condition", "syntax error: '=' where '==' was meant",
     r"{at}.*'then' expected", after={"output": [wrong("if sim:dimension() = 2 then print('2D') end")]})
case("syntax_goto_missing_label", "syntax error: goto a label that does not exist",
     r"syntax_goto_missing_label\.lua:\d+:.*no visible label 'finish'", after={"output": [wrong("goto finish")]})
case("syntax_number_name", "syntax error: a variable name starting with a digit",
     r"{at}.*malformed number", after={"output": [wrong("local 2nd = 1")]})
case("syntax_unfinished_comment", "syntax error: a long comment never closed",
     r"syntax_unfinished_comment\.lua:\d+:.*unfinished long comment", after={"output": [wrong("--[[ the run is below")]})
case("syntax_return_not_last", "syntax error: statements after a return",
     r"syntax_return_not_last\.lua:\d+:.*<eof>'? expected", after={"output": [wrong("return 1")]})
case("syntax_unbalanced_paren", "syntax error: a parenthesis never closed",
     r"syntax_unbalanced_paren\.lua:\d+:.*'\)' expected \(to close '\(' at line {line}\)", after={"output": [wrong("print((1 + 2)")]})

# ---------------------------------------------------------------------------
# Runtime errors in the scene's own logic
# ---------------------------------------------------------------------------
case("lua_nil_arithmetic", "runtime error: arithmetic on nil",
     r"{at}.*undeclared global 'undefined_radius'", after={"output": [wrong("local x = undefined_radius * 2")]})
case("lua_misspelled_global", "runtime error: a misspelled global function",
     r"{at}.*undeclared global 'simulaton' \(did you mean 'simulation'\?\)", replace={"sim": wrong("local sim = simulaton { dimension = 2 }")},
     drop=["material", "wall_material", "contact", "wall_contact", "wall", "fill", "output", "run"])
case("lua_index_nil", "runtime error: indexing a field that does not exist",
     r"{at}.*no method 'settings'", after={"output": [wrong("local r = sim.settings.radius")]})
case("lua_concat_table", "runtime error: concatenating a table",
     r"{at}.*attempt to concatenate a table value", after={"output": [wrong('print("particles: " .. sim:particles())')]})
case("lua_error_string", "runtime error: the scene raises its own error",
     r"{at}.*the scene gave up on purpose", after={"output": [wrong('error("the scene gave up on purpose")')]})
case("lua_error_table", "runtime error: an error object that is a table",
     r"error object is a table value[\s\S]*{at}", after={"output": [wrong("error({ code = 42 })")]})
case("lua_error_nil", "runtime error: an error object that is nil",
     r"error object is a nil value[\s\S]*{at}", after={"output": [wrong("error(nil)")]})
case("lua_error_table_tostring", "runtime error: an error table whose __tostring raises",
     r"error object is a table value[\s\S]*{at}",
     after={"output": [wrong("error(setmetatable({}, { __tostring = function() error('no') end }))")]})
case("lua_assert_false", "runtime error: a failed assert",
     r"{at}.*the drum must be empty", after={"output": [wrong('assert(#sim:particles() == 0, "the drum must be empty")')]})
case("lua_method_with_dot", "runtime error: a method called with '.' instead of ':'",
     r"{at}.*run", replace={"run": wrong("sim.run { steps = 10 }")})
case("lua_require_missing", "runtime error: require of a module that does not exist",
     r"{at}.*module 'granule\.nosuch' not found", after={"output": [wrong('local m = require "granule.nosuch"')]})
case("lua_unknown_method", "runtime error: a simulation method that does not exist",
     r"{at}.*no method 'wall_sphere'", after={"wall": [wrong('sim:wall_sphere { name = "ball", center = { 0, 0 }, radius = 0.01, material = "steel" }')]})
case("lua_stack_overflow", "runtime error: unbounded recursion (a stack overflow, not a hang)",
     r"lua_stack_overflow\.lua:\d+:.*stack overflow", after={"output": ["local function deeper(n) return 1 + deeper(n + 1) end", wrong("deeper(1)")]})
case("lua_string_arith", "runtime error: arithmetic on a word",
     r"{at}.*attempt to add a 'string'", after={"output": [wrong('local r = "big" + 1')]})

# ---------------------------------------------------------------------------
# simulation { }
# ---------------------------------------------------------------------------
S = "sim"
for name, text, expect in [
    ("sim_dimension_4", "dimension = 4", r"{at}.*dimension"),
    ("sim_dimension_text", 'dimension = "2"', r"{at}.*dimension"),
    ("sim_dimension_fraction", "dimension = 2.5", r"{at}.*dimension"),
    ("sim_dimension_nan", "dimension = 0/0", r"{at}.*dimension"),
    ("sim_time_step_negative", "dimension = 2, time_step = -1e-6", r"{at}.*time_step"),
    ("sim_time_step_nan", "dimension = 2, time_step = 0/0", r"{at}.*time_step"),
    ("sim_time_step_inf", "dimension = 2, time_step = math.huge", r"{at}.*time_step"),
    ("sim_steps_per_contact_zero", "dimension = 2, steps_per_contact = 0", r"{at}.*steps_per_contact"),
    ("sim_steps_per_contact_negative", "dimension = 2, steps_per_contact = -5", r"{at}.*steps_per_contact"),
    ("sim_steps_per_contact_nan", "dimension = 2, steps_per_contact = 0/0", r"{at}.*steps_per_contact"),
    ("sim_steps_per_contact_text", 'dimension = 2, steps_per_contact = "many"', r"{at}.*steps_per_contact"),
    ("sim_skin_negative", "dimension = 2, skin = -1e-4", r"{at}.*skin"),
    ("sim_skin_nan", "dimension = 2, skin = 0/0", r"{at}.*skin"),
    ("sim_record_contacts_text", 'dimension = 2, record_contacts = "yes"', r"{at}.*record_contacts"),
    ("sim_threads_negative", "dimension = 2, threads = -2", r"{at}.*threads"),
    ("sim_threads_fraction", "dimension = 2, threads = 1.5", r"{at}.*threads"),
    ("sim_unknown_key", "dimension = 2, dimensions = 2", r"{at}.*unknown key 'dimensions'"),
    ("sim_periodic_in_2d", 'dimension = 2, periodic = { axis = "x", origin = 0, length = 0.01 }', r"{at}.*periodic"),
]:
    case(name, f"simulation {{ {text} }}: a bad setting", expect,
         replace={"sim": wrong(f"local sim = simulation {{ {text} }}")})
case("sim_not_a_table", "simulation called with a number instead of a table",
     r"{at}.*simulation", replace={"sim": wrong("local sim = simulation(2)")}, drop=["material", "wall_material", "contact", "wall_contact", "wall", "fill", "output", "run"])
for name, text, expect in [
    ("sim_periodic_bad_axis", 'periodic = { axis = "w", origin = 0, length = 0.01 }', r"{at}.*axis"),
    ("sim_periodic_zero_length", 'periodic = { axis = "x", origin = 0, length = 0 }', r"{at}.*length"),
    ("sim_periodic_nan_origin", 'periodic = { axis = "x", origin = 0/0, length = 0.01 }', r"{at}.*origin"),
]:
    case(name, f"simulation {{ {text} }}: a bad periodic axis", expect,
         replace={"sim": wrong(f"local sim = simulation {{ dimension = 3, {text} }}")}, base=BASE3)
case("periodic_wall_across", "a floor across the periodic axis: a particle wrapping past it would land "
     "below it (refused at the run's preparation, naming the wall)",
     r"{at}.*wall 'floor' is a plane crossing the periodic axis",
     replace={"sim": 'local sim = simulation { dimension = 3, periodic = { axis = "z", origin = 0, length = 0.01 } }',
              "run": wrong("sim:run { steps = 10 }")}, base=BASE3)
case("sim_skin_larger_than_scene", "a neighbour skin (1 km) far larger than the scene (2 cm)",
     r"skin 1000 m is larger than the scene", replace={"sim": wrong("local sim = simulation { dimension = 2, skin = 1000 }")})
case("sim_time_step_above_limit", "a fixed time step far above the stability limit",
     r"time_step 0\.001 s is above the stability limit", replace={"sim": wrong("local sim = simulation { dimension = 2, time_step = 1e-3 }")})
case("sim_steps_per_contact_one", "steps_per_contact = 1: one step per contact, above the stability limit",
     r"steps_per_contact = 1 gives a time step .* above the stability limit", replace={"sim": wrong("local sim = simulation { dimension = 2, steps_per_contact = 1 }")})
case("sim_steps_per_contact_hertz", "steps_per_contact = 10 with Hertz's laws, whose rule is Thornton's 8 T_R / n",
     r"steps_per_contact = 10 gives a time step .* \(8 T_R / n \(Eqs\. 6\.1-6\.2\) for glass-glass .* above the stability limit",
     replace={"sim": wrong("local sim = simulation { dimension = 3, steps_per_contact = 10 }")}, base=BASE3)

# ---------------------------------------------------------------------------
# sim:material
# ---------------------------------------------------------------------------
for name, text, expect in [
    ("material_no_name", "density = 2500", r"{at}.*name"),
    ("material_name_number", "name = 1, density = 2500", r"{at}.*name"),
    ("material_density_negative", 'name = "glass", density = -2500', r"{at}.*density"),
    ("material_density_nan", 'name = "glass", density = 0/0', r"{at}.*density"),
    ("material_density_inf", 'name = "glass", density = math.huge', r"{at}.*density"),
    ("material_density_text", 'name = "glass", density = "heavy"', r"{at}.*density"),
    ("material_young_negative", 'name = "glass", density = 2500, young = -1e9', r"{at}.*young"),
    ("material_poisson_above_half", 'name = "glass", density = 2500, poisson = 0.6', r"{at}.*poisson"),
    ("material_poisson_minus_one", 'name = "glass", density = 2500, poisson = -1', r"{at}.*poisson"),
    ("material_poisson_nan", 'name = "glass", density = 2500, poisson = 0/0', r"{at}.*poisson"),
    ("material_surface_energy_negative", 'name = "glass", density = 2500, surface_energy = -1', r"{at}.*surface_energy"),
    ("material_misspelled_density", 'name = "glass", densty = 2500', r"{at}.*unknown key 'densty'"),
    ("material_empty_name", 'name = "", density = 2500', r"{at}.*name"),
]:
    case(name, f"sim:material {{ {text} }}: a bad property", expect,
         replace={"material": wrong(f"sim:material {{ {text} }}")})
case("material_declared_twice", "the same material name declared twice",
     r"{at}.*glass", after={"material": [wrong('sim:material { name = "glass", density = 1000 }')]})
case("material_name_with_slash", "a material named with a '/', which would nest its HDF5 group",
     r"{at}.*material: name 'glass/2' holds a '/'", after={"material": [wrong('sim:material { name = "glass/2", density = 1000 }')]})
case("wall_name_with_newline", "a wall named with a newline, which would split the checkpoint's lines",
     r"{at}.*wall: name .* holds a '/' or a control character",
     after={"wall": [wrong('sim:wall_plane { name = "lid\\nright", point = { 0, 0.009 }, normal = { 0, -1 }, material = "steel" }')]})
case("material_zero_density_particle", "particles of a material with density 0 (a wall material)",
     r"{at}.*density", replace={"fill": wrong('sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "steel", seed = 2 }')},
     after={"wall_contact": ['sim:contact { "steel", "steel", model = "linear", k_normal = 1e4, restitution = 0.8 }']})

# ---------------------------------------------------------------------------
# sim:contact, per model
# ---------------------------------------------------------------------------
LIN = 'sim:contact { "glass", "glass", model = "linear", %s }'
for name, text, expect in [
    ("linear_k_normal_missing", "restitution = 0.8", r"{at}.*k_normal"),
    ("linear_k_normal_zero", "k_normal = 0, restitution = 0.8", r"{at}.*k_normal"),
    ("linear_k_normal_negative", "k_normal = -1e4, restitution = 0.8", r"{at}.*k_normal"),
    ("linear_k_normal_nan", "k_normal = 0/0, restitution = 0.8", r"{at}.*k_normal"),
    ("linear_k_normal_inf", "k_normal = math.huge, restitution = 0.8", r"{at}.*k_normal"),
    ("linear_k_normal_text", 'k_normal = "stiff", restitution = 0.8', r"{at}.*k_normal"),
    ("linear_restitution_zero", "k_normal = 1e4, restitution = 0", r"{at}.*restitution"),
    ("linear_restitution_above_one", "k_normal = 1e4, restitution = 1.5", r"{at}.*restitution"),
    ("linear_restitution_negative", "k_normal = 1e4, restitution = -0.1", r"{at}.*restitution"),
    ("linear_restitution_nan", "k_normal = 1e4, restitution = 0/0", r"{at}.*restitution"),
    ("linear_friction_negative", "k_normal = 1e4, restitution = 0.8, friction = -0.3", r"{at}.*friction"),
    ("linear_friction_nan", "k_normal = 1e4, restitution = 0.8, friction = 0/0", r"{at}.*friction"),
    ("linear_tangential_ratio_negative", "k_normal = 1e4, restitution = 0.8, tangential_ratio = -1", r"{at}.*tangential_ratio"),
    ("linear_damping_ratio_nan", "k_normal = 1e4, restitution = 0.8, tangential_damping_ratio = 0/0", r"{at}.*tangential_damping_ratio"),
    ("linear_allow_tension_two", "k_normal = 1e4, restitution = 0.8, allow_tension = 2", r"{at}.*allow_tension"),
    ("linear_misspelled_key", "k_norml = 1e4, restitution = 0.8", r"{at}.*unknown.*'k_norml'"),
    ("linear_foreign_key", "k_normal = 1e4, restitution = 0.8, k_load = 1e4", r"{at}.*k_load"),
]:
    case(name, "linear contact: " + text, expect, replace={"contact": wrong(LIN % text)})
WB = 'sim:contact { "glass", "glass", model = "walton_braun", %s }'
for name, text, expect in [
    ("walton_braun_k_load_missing", "restitution = 0.8", r"{at}.*k_load"),
    ("walton_braun_k_load_negative", "k_load = -2e4, restitution = 0.8", r"{at}.*k_load"),
    ("walton_braun_restitution_zero", "k_load = 2e4, restitution = 0", r"{at}.*restitution"),
    ("walton_braun_restitution_above_one", "k_load = 2e4, restitution = 1.2", r"{at}.*restitution"),
    ("walton_braun_slip_exponent_zero", "k_load = 2e4, restitution = 0.8, slip_exponent = 0", r"{at}.*slip_exponent"),
    ("walton_braun_slip_exponent_nan", "k_load = 2e4, restitution = 0.8, slip_exponent = 0/0", r"{at}.*slip_exponent"),
    ("walton_braun_friction_inf", "k_load = 2e4, restitution = 0.8, friction = math.huge", r"{at}.*friction"),
    ("walton_braun_tangential_ratio_zero", "k_load = 2e4, restitution = 0.8, friction = 0.3, tangential_ratio = 0", r"{at}.*tangential_ratio"),
    ("walton_braun_misspelled_key", "k_lod = 2e4, restitution = 0.8", r"{at}.*unknown.*'k_lod'"),
]:
    case(name, "walton_braun contact: " + text, expect, replace={"contact": wrong(WB % text)})
HM = 'sim:contact { "glass", "glass", model = "hertz_mindlin", %s }'
for name, text, expect in [
    ("hertz_mindlin_restitution_missing", "friction = 0.3", r"{at}.*restitution"),
    ("hertz_mindlin_restitution_nan", "restitution = 0/0", r"{at}.*restitution"),
    ("hertz_mindlin_calibrate_three", "restitution = 0.8, calibrate_restitution = 3", r"{at}.*calibrate_restitution"),
    ("hertz_mindlin_misspelled_key", "restitution = 0.8, fricton = 0.3", r"{at}.*unknown.*'fricton'"),
]:
    case(name, "hertz_mindlin contact: " + text, expect, replace={"contact": wrong(HM % text)}, base=BASE3)
case("hertz_mindlin_no_young", "hertz_mindlin between materials without Young's modulus",
     r"young", replace={"material": wrong('sim:material { name = "glass", density = 2500 }')}, base=BASE3)
TE = 'sim:contact { "glass", "glass", model = "thornton_elastic", %s }'
for name, text, expect in [
    ("thornton_elastic_restitution", "restitution = 0.8", r"{at}.*restitution"),
    ("thornton_elastic_friction_negative", "friction = -1", r"{at}.*friction"),
    ("thornton_elastic_friction_text", 'friction = "rough"', r"{at}.*friction"),
]:
    case(name, "thornton_elastic contact: " + text, expect, replace={"contact": wrong(TE % text)}, base=BASE3)
case("thornton_elastic_poisson_missing_young", "thornton_elastic between materials with zero Young's modulus",
     r"young", replace={"material": wrong('sim:material { name = "glass", density = 2500, young = 0, poisson = 0.3 }'),
                        "contact": TE % "friction = 0.3"}, base=BASE3)
TJ = 'sim:contact { "glass", "glass", model = "thornton_jkr", %s }'
for name, text, expect in [
    ("thornton_jkr_surface_energy_nan", "friction = 0.3, surface_energy = 0/0", r"{at}.*surface_energy"),
    ("thornton_jkr_surface_energy_negative", "friction = 0.3, surface_energy = -2", r"{at}.*surface_energy"),
    ("thornton_jkr_surface_energy_inf", "friction = 0.3, surface_energy = math.huge", r"{at}.*surface_energy"),
    ("thornton_jkr_misspelled_key", "friction = 0.3, surface_enrgy = 0.05", r"{at}.*unknown.*'surface_enrgy'"),
]:
    case(name, "thornton_jkr contact: " + text, expect, replace={"contact": wrong(TJ % text)}, base=BASE3)
for name, line, expect in [
    ("contact_unknown_model", 'sim:contact { "glass", "glass", model = "hooke", k_normal = 1e4, restitution = 0.8 }', r"{at}.*hooke"),
    ("contact_model_missing", 'sim:contact { "glass", "glass", k_normal = 1e4, restitution = 0.8 }', r"{at}.*model"),
    ("contact_model_number", 'sim:contact { "glass", "glass", model = 1, k_normal = 1e4, restitution = 0.8 }', r"{at}.*model"),
    ("contact_undeclared_material", 'sim:contact { "glass", "sand", model = "linear", k_normal = 1e4, restitution = 0.8 }', r"{at}.*sand"),
    ("contact_one_material", 'sim:contact { "glass", model = "linear", k_normal = 1e4, restitution = 0.8 }', r"{at}.*material"),
    ("contact_material_number", 'sim:contact { "glass", 7, model = "linear", k_normal = 1e4, restitution = 0.8 }', r"{at}.*material"),
    ("contact_unknown_and_missing", 'sim:contact { "glass", "glass", model = "linear", k_norml = 1e4 }', r"{at}.*unknown (key|parameter) 'k_norml'"),
]:
    case(name, "sim:contact: " + name.replace("contact_", "").replace("_", " "), expect, replace={"contact": wrong(line)})
case("contact_declared_twice", "a second sim:contact for a pair already declared",
     r"{at}.*declared twice: first at \S*contact_declared_twice\.lua:6\b", after={"contact": [wrong('sim:contact { "glass", "glass", model = "linear", k_normal = 2e4, restitution = 0.7 }')]})
case("bond_normal_stiffness_missing", "sim:bond without normal_stiffness, its shear_stiffness given: the missing key is named, not the present one",
     r"{at}.*bond: 'normal_stiffness' is required",
     after={"fill": [wrong('sim:bond { shear_stiffness = 1e9, tensile_strength = 1e6, shear_strength = 1e6 }')]})
case("contact_pair_missing", "particles of a material pair that has no contact law",
     r"no contact law for materials 'glass' and 'steel'", drop=["wall_contact"])

# ---------------------------------------------------------------------------
# walls
# ---------------------------------------------------------------------------
for name, line, expect in [
    ("cylinder_radius_zero", 'sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0, material = "steel" }', r"{at}.*radius"),
    ("cylinder_radius_negative", 'sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = -0.01, material = "steel" }', r"{at}.*radius"),
    ("cylinder_radius_nan", 'sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0/0, material = "steel" }', r"{at}.*radius"),
    ("cylinder_center_nan", 'sim:wall_cylinder { name = "drum", center = { 0/0, 0 }, radius = 0.01, material = "steel" }', r"{at}.*center"),
    ("cylinder_center_short", 'sim:wall_cylinder { name = "drum", center = { 0 }, radius = 0.01, material = "steel" }', r"{at}.*center"),
    ("cylinder_center_text", 'sim:wall_cylinder { name = "drum", center = "origin", radius = 0.01, material = "steel" }', r"{at}.*center"),
    ("cylinder_inside_text", 'sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, inside = "yes", material = "steel" }', r"{at}.*inside"),
    ("cylinder_angular_velocity_nan", 'sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, angular_velocity = 0/0, material = "steel" }', r"{at}.*angular_velocity"),
    ("cylinder_angular_velocity_inf", 'sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, angular_velocity = -math.huge, material = "steel" }', r"{at}.*angular_velocity"),
    ("cylinder_material_undeclared", 'sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "iron" }', r"{at}.*iron"),
    ("cylinder_no_name", 'sim:wall_cylinder { center = { 0, 0 }, radius = 0.01, material = "steel" }', r"{at}.*name"),
    ("cylinder_misspelled_radius", 'sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, raduis = 0.01, material = "steel" }', r"{at}.*unknown key 'raduis'"),
]:
    case(name, "sim:wall_cylinder: " + name.replace("cylinder_", "").replace("_", " "), expect, replace={"wall": wrong(line)})
case("wall_name_twice", "two walls with the same name",
     r"{at}.*drum", after={"wall": [wrong('sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.02, material = "steel" }')]})
PL = 'sim:wall_plane { name = "floor", %s, material = "steel" }'
for name, text, expect in [
    ("plane_normal_zero", "point = { 0, 0, 0 }, normal = { 0, 0, 0 }", r"{at}.*normal"),
    ("plane_normal_nan", "point = { 0, 0, 0 }, normal = { 0, 0/0, 1 }", r"{at}.*normal"),
    ("plane_normal_inf", "point = { 0, 0, 0 }, normal = { 0, 0, math.huge }", r"{at}.*normal"),
    ("plane_point_missing", "normal = { 0, 0, 1 }", r"{at}.*point"),
    ("plane_point_2d_in_3d", "point = { 0, 0 }, normal = { 0, 0, 1 }", r"{at}.*point"),
    ("plane_point_words", 'point = { "a", "b", "c" }, normal = { 0, 0, 1 }', r"{at}.*point"),
    ("plane_velocity_inf", "point = { 0, 0, 0 }, normal = { 0, 0, 1 }, velocity = { math.huge, 0, 0 }", r"{at}.*velocity"),
    ("plane_misspelled_normal", "point = { 0, 0, 0 }, norml = { 0, 0, 1 }", r"{at}.*unknown key 'norml'"),
]:
    case(name, "sim:wall_plane: " + text, expect, replace={"wall": wrong(PL % text)}, base=BASE3)
# Finite walls (docs/walls.md), each bad in one parameter, added after the floor.
FW = [
    ("plane_size_one_number", 'sim:wall_plane { name = "plate", point = { 0, 0, 0.01 }, normal = { 0, 0, 1 }, size = { 0.1 }, material = "steel" }', r"{at}.*size"),
    ("plane_size_negative", 'sim:wall_plane { name = "plate", point = { 0, 0, 0.01 }, normal = { 0, 0, 1 }, size = { 0.1, -1 }, material = "steel" }', r"{at}.*size\[2\] must be > 0"),
    ("plane_side_along_normal", 'sim:wall_plane { name = "plate", point = { 0, 0, 0.01 }, normal = { 0, 0, 1 }, size = { 0.1, 0.1 }, side = { 0, 0, 3 }, material = "steel" }', r"{at}.*side must not be parallel"),
    ("plane_side_without_size", 'sim:wall_plane { name = "plate", point = { 0, 0, 0.01 }, normal = { 0, 0, 1 }, side = { 1, 0, 0 }, material = "steel" }', r"{at}.*'side'.*size"),
    ("disk_inner_above_outer", 'sim:wall_disk { name = "orifice", center = { 0, 0, 0.01 }, normal = { 0, 0, 1 }, radius = 0.01, inner_radius = 0.02, material = "steel" }', r"{at}.*inner_radius"),
    ("disk_normal_zero", 'sim:wall_disk { name = "orifice", center = { 0, 0, 0.01 }, normal = { 0, 0, 0 }, radius = 0.01, material = "steel" }', r"{at}.*normal must be non-zero"),
    ("disk_radius_nan", 'sim:wall_disk { name = "orifice", center = { 0, 0, 0.01 }, normal = { 0, 0, 1 }, radius = 0/0, material = "steel" }', r"{at}.*radius"),
    ("cone_bounds_reversed", 'sim:wall_cone { name = "hopper", center = { 0, 0, 0.01 }, axis = { 0, 0, 1 }, bounds = { 0.1, 0 }, radii = { 0.01, 0.05 }, material = "steel" }', r"{at}.*bounds"),
    ("cone_radii_zero", 'sim:wall_cone { name = "hopper", center = { 0, 0, 0.01 }, axis = { 0, 0, 1 }, bounds = { 0, 0.1 }, radii = { 0, 0 }, material = "steel" }', r"{at}.*radii must not both be 0"),
    ("cone_radii_three", 'sim:wall_cone { name = "hopper", center = { 0, 0, 0.01 }, axis = { 0, 0, 1 }, bounds = { 0, 0.1 }, radii = { 0, 0.1, 0.2 }, material = "steel" }', r"{at}.*radii"),
    ("tube_bounds_one", 'sim:wall_cylinder { name = "tube", center = { 0, 0, 0 }, radius = 0.01, bounds = { 0.1 }, material = "steel" }', r"{at}.*bounds"),
    ("tube_velocity_unbounded", 'sim:wall_cylinder { name = "tube", center = { 0, 0, 0 }, radius = 0.01, velocity = { 0, 0, 1 }, material = "steel" }', r"{at}.*bounds"),
]
for name, line, expect in FW:
    case(name, name.replace("_", " "), expect, after={"wall": [wrong(line)]}, base=BASE3)
case("tube_bounds_in_2d", "a 2D cylinder with bounds",
     r"{at}.*no bounds", replace={"wall": wrong('sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, bounds = { 0, 1 }, material = "steel" }')})
case("disk_turning_in_2d", "a 2D disk that turns",
     r"{at}.*angular_velocity", after={"wall": [wrong('sim:wall_disk { name = "plate", center = { 0, 0 }, normal = { 0, 1 }, radius = 0.005, angular_velocity = 1, material = "steel" }')]})
case("cylinder_axis_zero", "a 3D cylinder with a zero axis",
     r"{at}.*axis", replace={"wall": wrong('sim:wall_cylinder { name = "tube", center = { 0, 0, 0 }, axis = { 0, 0, 0 }, radius = 0.01, material = "steel" }')}, base=BASE3)
case("wall_particle_outside", "a particle placed outside the drum",
     r"particle 5 .* outside wall 'drum'", after={"fill": [wrong('sim:add_particle { position = { 0.05, 0 }, radius = 3e-4, material = "glass" }')]})
case("wall_particle_centre_through_plane", "a particle whose centre is beyond the floor",
     r"particle 5 .* outside wall 'floor'", after={"fill": [wrong('sim:add_particle { position = { 0, 0, -1e-4 }, radius = 3e-4, material = "glass" }')]}, base=BASE3)
case("set_wall_unknown", "sim:set_wall of a wall that does not exist",
     r"{at}.*chamber", after={"output": [wrong('sim:set_wall("chamber", { angular_velocity = 10 })')]})
case("set_wall_velocity_on_cylinder", "a plane's velocity given to a cylinder",
     r"{at}.*velocity", after={"output": [wrong('sim:set_wall("drum", { velocity = { 1, 0 } })')]})
case("set_wall_angular_on_plane", "a cylinder's angular velocity given to a plane",
     r"{at}.*'floor' is a plane", after={"output": [wrong('sim:set_wall("floor", { angular_velocity = 10 })')]}, base=BASE3)
case("set_wall_nan", "a moving wall given a NaN angular velocity",
     r"{at}.*angular_velocity", after={"output": [wrong('sim:set_wall("drum", { angular_velocity = 0/0 })')]})
case("set_wall_no_table", "sim:set_wall without its table",
     r"{at}.*set_wall", after={"output": [wrong('sim:set_wall("drum")')]})
case("set_wall_plane_velocity_huge", "a plane moved at 1e300 m/s",
     r"wall 'floor' moves 1\.6\d*e\+294 m in one step.*slow the wall", after={"output": [wrong('sim:set_wall("floor", { velocity = { 0, 0, 1e300 } })')]}, base=BASE3)

# ---------------------------------------------------------------------------
# sim:fill
# ---------------------------------------------------------------------------
FILL = 'sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, %s }'
for name, text, expect in [
    ("fill_count_negative", 'count = -5, radius = 3e-4, material = "glass"', r"{at}.*count"),
    ("fill_count_fraction", 'count = 2.5, radius = 3e-4, material = "glass"', r"{at}.*count"),
    ("fill_count_nan", 'count = 0/0, radius = 3e-4, material = "glass"', r"{at}.*count"),
    ("fill_count_text", 'count = "five", radius = 3e-4, material = "glass"', r"{at}.*count"),
    ("fill_count_huge", 'count = 1e12, radius = 3e-4, material = "glass"', r"{at}.*count"),
    ("fill_count_maxinteger", 'count = math.maxinteger, radius = 3e-4, material = "glass"', r"{at}.*count"),
    ("fill_radius_negative", 'count = 5, radius = -3e-4, material = "glass"', r"{at}.*radius"),
    ("fill_radius_nan", 'count = 5, radius = 0/0, material = "glass"', r"{at}.*radius"),
    ("fill_radius_inf", 'count = 5, radius = math.huge, material = "glass"', r"{at}.*radius"),
    ("fill_radius_too_large", 'count = 5, radius = 0.02, material = "glass"', r"{at}.*(radius|place|fit)"),
    ("fill_no_radius", 'count = 5, material = "glass"', r"{at}.*radius"),
    ("fill_radius_range_reversed", 'count = 5, radius_min = 4e-4, radius_max = 2e-4, material = "glass"', r"{at}.*radius_m"),
    ("fill_radii_empty", 'count = 5, radii = {}, material = "glass"', r"{at}.*radii"),
    ("fill_radii_negative", 'count = 5, radii = { 3e-4, -3e-4 }, material = "glass"', r"{at}.*radi"),
    ("fill_material_undeclared", 'count = 5, radius = 3e-4, material = "sand"', r"{at}.*sand"),
    ("fill_material_missing", 'count = 5, radius = 3e-4', r"{at}.*material"),
    ("fill_seed_text", 'count = 5, radius = 3e-4, material = "glass", seed = "lucky"', r"{at}.*seed"),
    ("fill_seed_fraction", 'count = 5, radius = 3e-4, material = "glass", seed = 1.5', r"{at}.*seed"),
    ("fill_max_speed_nan", 'count = 5, radius = 3e-4, material = "glass", max_speed = 0/0', r"{at}.*max_speed"),
    ("fill_max_speed_negative", 'count = 5, radius = 3e-4, material = "glass", max_speed = -1', r"{at}.*max_speed"),
    ("fill_max_attempts_negative", 'count = 5, radius = 3e-4, material = "glass", max_attempts = -1', r"{at}.*max_attempts"),
    ("fill_no_overlap_too_many", 'count = 2000, radius = 3e-4, material = "glass", overlap = false', r"{at}.*(place|attempt|count)"),
    ("fill_overlap_text", 'count = 5, radius = 3e-4, material = "glass", overlap = "no"', r"{at}.*overlap"),
    ("fill_misspelled_radius", 'count = 5, radis = 3e-4, material = "glass"', r"{at}.*unknown key 'radis'"),
]:
    case(name, "sim:fill: " + text, expect, replace={"fill": wrong(FILL % text)})
case("scale_velocities_listed_twice", "sim:scale_velocities names one particle twice (it would be scaled twice)",
     r"{at}.*lists particle 1 twice", after={"fill": [wrong("sim:scale_velocities { factor = 2, particles = { 1, 2, 1 } }")]})
for name, line, expect in [
    ("fill_region_missing", 'sim:fill { count = 5, radius = 3e-4, material = "glass" }', r"{at}.*region"),
    ("fill_region_unknown_shape", 'sim:fill { region = { hexagon = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass" }', r"{at}.*fill\.region"),
    ("fill_region_radius_negative", 'sim:fill { region = { circle = { center = { 0, 0 }, radius = -0.008 } }, count = 5, radius = 3e-4, material = "glass" }', r"{at}.*radius"),
    ("fill_region_center_nan", 'sim:fill { region = { circle = { center = { 0/0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass" }', r"{at}.*center"),
    ("fill_region_outside_walls", 'sim:fill { region = { circle = { center = { 1, 1 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass" }', r"{at}.*(place|wall|attempt)"),
    ("fill_region_sphere_in_2d", 'sim:fill { region = { sphere = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass" }', r"{at}.*fill\.region"),
]:
    case(name, "sim:fill: " + name.replace("fill_", "").replace("_", " "), expect, replace={"fill": wrong(line)})
case("fill_box_reversed", "a fill box with lo above hi",
     r"{at}.*box", replace={"fill": wrong('sim:fill { region = { box = { lo = { 0.002, 0.002, 0.004 }, hi = { -0.002, -0.002, 0.001 } } }, count = 5, radius = 3e-4, material = "glass" }')}, base=BASE3)
case("fill_region_misspelled_radius", "a misspelled key inside fill's region (a nested table)",
     r"{at}.*unknown key 'radis' \(did you mean 'radius'\?\)", replace={"fill": wrong('sim:fill { region = { circle = { center = { 0, 0 }, radis = 0.008 } }, count = 5, radius = 3e-4, material = "glass" }')})
case("fill_huge_count_memory", "a fill of 5e8 particles, far more memory than the machine has",
     r"{at}.*particles need about .* GB", replace={"fill": wrong('sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5e8, radius = 1e-9, material = "glass" }')})

# ---------------------------------------------------------------------------
# sim:add_particle
# ---------------------------------------------------------------------------
AP = 'sim:add_particle { %s }'
for name, text, expect in [
    ("particle_position_missing", 'radius = 3e-4, material = "glass"', r"{at}.*position"),
    ("particle_position_nan", 'position = { 0/0, 0 }, radius = 3e-4, material = "glass"', r"{at}.*position"),
    ("particle_position_inf", 'position = { 0, math.huge }, radius = 3e-4, material = "glass"', r"{at}.*position"),
    ("particle_position_one_component", 'position = { 0 }, radius = 3e-4, material = "glass"', r"{at}.*position"),
    ("particle_radius_zero", 'position = { 0, 0 }, radius = 0, material = "glass"', r"{at}.*radius"),
    ("particle_radius_nan", 'position = { 0, 0 }, radius = 0/0, material = "glass"', r"{at}.*radius"),
    ("particle_radius_inf", 'position = { 0, 0 }, radius = math.huge, material = "glass"', r"{at}.*radius"),
    ("particle_radius_text", 'position = { 0, 0 }, radius = "small", material = "glass"', r"{at}.*radius"),
    ("particle_material_undeclared", 'position = { 0, 0 }, radius = 3e-4, material = "sand"', r"{at}.*sand"),
    ("particle_velocity_inf", 'position = { 0, 0 }, radius = 3e-4, material = "glass", velocity = { math.huge, 0 }', r"{at}.*velocity"),
    ("particle_velocity_nan", 'position = { 0, 0 }, radius = 3e-4, material = "glass", velocity = { 0, 0/0 }', r"{at}.*velocity"),
    ("particle_spin_table_in_2d", 'position = { 0, 0 }, radius = 3e-4, material = "glass", spin = { 0, 0, 1 }', r"{at}.*spin"),
    ("particle_spin_nan", 'position = { 0, 0 }, radius = 3e-4, material = "glass", spin = 0/0', r"{at}.*spin"),
    ("particle_fixed_text", 'position = { 0, 0 }, radius = 3e-4, material = "glass", fixed = "yes"', r"{at}.*fixed"),
    ("particle_misspelled_radius", 'position = { 0, 0 }, radus = 3e-4, material = "glass"', r"{at}.*unknown key 'radus'"),
]:
    case(name, "sim:add_particle: " + text, expect, replace={"fill": wrong(AP % text)})
case("particle_not_a_table", "sim:add_particle given positional arguments",
     r"{at}.*add_particle", replace={"fill": wrong('sim:add_particle({ 0, 0 }, 3e-4, "glass")')})
case("particles_pass_through", "two particles closing at 2000 m/s: in one step they overlap by more than a radius",
     r"particles 0 and 1 pass through each other", replace={"fill": 'sim:add_particle { position = { -4e-4, 0 }, radius = 3e-4, material = "glass", velocity = { 1000, 0 } }'},
     after={"fill": [wrong('sim:add_particle { position = { 4e-4, 0 }, radius = 3e-4, material = "glass", velocity = { -1000, 0 } }')]})
case("run_before_particles", "a run before any particle was added",
     r"{at}.*particle", drop=["fill"], replace={"run": wrong("sim:run { steps = 10 }")})

# ---------------------------------------------------------------------------
# gravity and central fields
# ---------------------------------------------------------------------------
for name, line, expect in [
    ("gravity_no_argument", "sim:gravity()", r"{at}.*gravity"),
    ("gravity_nan", "sim:gravity { 0, 0/0 }", r"{at}.*gravity"),
    ("gravity_inf", "sim:gravity { 0, -math.huge }", r"{at}.*gravity"),
    ("gravity_three_in_2d", "sim:gravity { 0, -9.81, 5 }", r"{at}.*gravity"),
    ("gravity_text", 'sim:gravity("down")', r"{at}.*gravity"),
    ("central_strength_negative", "sim:central_field { point = { 0, 0 }, strength = -1 }", r"{at}.*strength"),
    ("central_strength_nan", "sim:central_field { point = { 0, 0 }, strength = 0/0 }", r"{at}.*strength"),
    ("central_point_missing", "sim:central_field { strength = 1 }", r"{at}.*point"),
    ("central_point_inf", "sim:central_field { point = { math.huge, 0 }, strength = 1 }", r"{at}.*point"),
    ("central_misspelled_strength", "sim:central_field { point = { 0, 0 }, strenght = 1 }", r"{at}.*unknown key 'strenght'"),
    ("central_set_strength_nan", "sim:central_field { point = { 0, 0 }, strength = 1 }; sim:set_central_strength(0/0)", r"{at}.*strength"),
    ("central_set_strength_text", 'sim:central_field { point = { 0, 0 }, strength = 1 }; sim:set_central_strength("strong")', r"{at}.*strength"),
]:
    case(name, name.replace("_", " "), expect, after={"fill": [wrong(line)]})

# ---------------------------------------------------------------------------
# output, snapshot, series, append
# ---------------------------------------------------------------------------
for name, line, expect in [
    ("output_file_table", "sim:output { file = { 'a.h5' } }", r"{at}.*file"),
    ("output_snapshot_every_negative", "sim:output { snapshot_every = -1 }", r"{at}.*snapshot_every"),
    ("output_snapshot_every_nan", "sim:output { snapshot_every = 0/0 }", r"{at}.*snapshot_every"),
    ("output_series_every_negative", "sim:output { series_every = -1e-3 }", r"{at}.*series_every"),
    ("output_xdmf_text", 'sim:output { xdmf = "no" }', r"{at}.*xdmf"),
    ("output_misspelled_key", "sim:output { snapshot_evry = 1e-3 }", r"{at}.*unknown key 'snapshot_evry'"),
]:
    case(name, name.replace("_", " "), expect, replace={"output": wrong(line)})
case("snapshot_without_output", "sim:snapshot before any sim:output",
     r"{at}.*output", drop=["output"], after={"fill": [wrong("sim:snapshot()")]})
for name, line, expect in [
    ("series_name_with_slash", 'sim:series("a/b", { "time" })', r"{at}.*a/b"),
    ("series_no_columns", 'sim:series("probe", {})', r"{at}.*column"),
    ("series_column_number", 'sim:series("probe", { "time", 2 })', r"{at}.*column"),
    ("series_twice", 'sim:series("probe", { "time" }); sim:series("probe", { "time", "energy" })', r"{at}.*probe"),
    ("series_name_series", 'sim:series("series", { "time" })', r"{at}.*series"),
    ("append_undeclared", 'sim:append("probe", { 1 })', r"{at}.*probe"),
    ("append_wrong_count", 'sim:series("probe", { "time", "energy" }); sim:append("probe", { 1 })', r"{at}.*(column|value)"),
    ("append_nan", 'sim:series("probe", { "time", "energy" }); sim:append("probe", { 1, 0/0 })', r"{at}.*(finite|nan)"),
    ("append_inf", 'sim:series("probe", { "time", "energy" }); sim:append("probe", { math.huge, 1 })', r"{at}.*(finite|inf)"),
    ("append_text", 'sim:series("probe", { "time", "energy" }); sim:append("probe", { 1, "high" })', r"{at}.*(number|value)"),
    ("result_nan", "sim:result { restitution = 0/0 }", r"{at}.*restitution"),
]:
    case(name, name.replace("_", " "), expect, after={"output": [wrong(line)]})
case("series_without_output", "sim:series before any sim:output",
     r"{at}.*output", drop=["output"], after={"fill": [wrong('sim:series("probe", { "time" })')]})

# ---------------------------------------------------------------------------
# checkpoints
# ---------------------------------------------------------------------------
for name, line, expect in [
    ("checkpoint_no_file", "sim:checkpoint { every_steps = 5 }", r"{at}.*file"),
    ("checkpoint_every_steps_zero", 'sim:checkpoint { file = "c.chk.h5", every_steps = 0 }', r"{at}.*every_steps"),
    ("checkpoint_every_steps_negative", 'sim:checkpoint { file = "c.chk.h5", every_steps = -10 }', r"{at}.*every_steps"),
    ("checkpoint_every_seconds_nan", 'sim:checkpoint { file = "c.chk.h5", every_seconds = 0/0 }', r"{at}.*every_seconds"),
    ("checkpoint_no_period", 'sim:checkpoint { file = "c.chk.h5" }', r"{at}.*every"),
    ("checkpoint_misspelled_key", 'sim:checkpoint { file = "c.chk.h5", every_step = 5 }', r"{at}.*unknown key 'every_step'"),
    ("save_checkpoint_no_file", "sim:save_checkpoint()", r"{at}.*(file|string)"),
    ("save_checkpoint_missing_dir", 'sim:save_checkpoint("no/such/dir/c.chk.h5")', r"{at}.*no/such/dir"),
]:
    case(name, name.replace("_", " "), expect, after={"output": [wrong(line)]})

# ---------------------------------------------------------------------------
# sim:every and its callbacks
# ---------------------------------------------------------------------------
for name, line, expect in [
    ("every_steps_zero", "sim:every { steps = 0, function(s) end }", r"{at}.*steps"),
    ("every_steps_negative", "sim:every { steps = -1, function(s) end }", r"{at}.*steps"),
    ("every_steps_fraction", "sim:every { steps = 2.5, function(s) end }", r"{at}.*steps"),
    ("every_time_zero", "sim:every { time = 0, function(s) end }", r"{at}.*time"),
    ("every_time_nan", "sim:every { time = 0/0, function(s) end }", r"{at}.*time"),
    ("every_no_function", "sim:every { steps = 1 }", r"{at}.*function"),
    ("every_no_period", "sim:every { function(s) end }", r"{at}.*(steps|time)"),
    ("every_steps_and_time", "sim:every { steps = 1, time = 1e-6, function(s) end }", r"{at}.*(steps|time)"),
    ("every_name_number", "sim:every { steps = 1, name = 7, function(s) end }", r"{at}.*name"),
    ("every_misspelled_key", "sim:every { step = 1, function(s) end }", r"{at}.*unknown key 'step'"),
    ("remove_hook_unknown", "sim:remove_hook(12345)", r"{at}.*12345"),
]:
    case(name, name.replace("_", " "), expect, after={"output": [wrong(line)]})
for name, body, expect in [
    ("callback_runtime_error", "local x = nil; x.y = 1", r"{at}.*attempt to index"),
    ("callback_error_string", 'error("the probe failed")', r"{at}.*the probe failed"),
    ("callback_error_table", "error({ reason = 'probe' })", r"{at}.*raised a table as its error"),
    ("callback_error_nil", "error(nil)", r"{at}.*raised a nil as its error"),
    ("callback_calls_run", "s:run { steps = 1 }", r"{at}.*run"),
    ("callback_append_nan", 's:append("probe", { s:time(), 0/0 })', r"{at}.*(finite|nan)"),
    ("callback_set_wall_nan", 's:set_wall("drum", { angular_velocity = 0/0 })', r"{at}.*angular_velocity"),
]:
    extra = ['sim:series("probe", { "time", "energy" })'] if "append" in name else []
    case(name, "sim:every callback: " + name.replace("callback_", "").replace("_", " "), expect,
         after={"output": extra + ["sim:every { steps = 2, function(s)", wrong("  " + body), "end }"]})
case("callback_removes_itself_then_errors", "a callback that removes its own hook and then raises",
     r"{at}.*after removing", after={"output": ["local id", "id = sim:every { steps = 2, function(s)", "  s:remove_hook(id)",
                                                wrong('  error("after removing")'), "end }"]})

# ---------------------------------------------------------------------------
# sim:run
# ---------------------------------------------------------------------------
for name, text, expect in [
    ("run_no_arguments", "sim:run()", r"{at}.*(duration|steps)"),
    ("run_empty_table", "sim:run {}", r"{at}.*(duration|steps)"),
    ("run_duration_and_steps", "sim:run { duration = 1e-5, steps = 10 }", r"{at}.*(duration|steps)"),
    ("run_duration_negative", "sim:run { duration = -1e-5 }", r"{at}.*duration"),
    ("run_duration_nan", "sim:run { duration = 0/0 }", r"{at}.*duration"),
    ("run_duration_inf", "sim:run { duration = math.huge }", r"{at}.*duration"),
    ("run_duration_huge", "sim:run { duration = 1e300 }", r"{at}.*duration"),
    ("run_duration_text", 'sim:run { duration = "long" }', r"{at}.*duration"),
    ("run_steps_negative", "sim:run { steps = -10 }", r"{at}.*steps"),
    ("run_steps_fraction", "sim:run { steps = 1.5 }", r"{at}.*steps"),
    ("run_steps_huge", "sim:run { steps = 1e300 }", r"{at}.*steps"),
    ("run_steps_nan", "sim:run { steps = 0/0 }", r"{at}.*steps"),
    ("run_stop_when_number", "sim:run { steps = 10, stop_when = 1 }", r"{at}.*stop_when"),
    ("run_check_every_zero", "sim:run { steps = 10, check_every = 0, stop_when = function() return false end }", r"{at}.*check_every"),
    ("run_check_every_negative", "sim:run { steps = 10, check_every = -3, stop_when = function() return false end }", r"{at}.*check_every"),
    ("run_misspelled_key", "sim:run { step = 10 }", r"{at}.*unknown key 'step'"),
    ("run_unknown_and_missing", "sim:run { durration = 1e-5 }", r"{at}.*unknown key 'durration'"),
]:
    case(name, name.replace("_", " "), expect, replace={"run": wrong(text)})
for name, body, expect in [
    ("stop_when_error", 'error("cannot decide")', r"{at}.*cannot decide"),
    ("stop_when_error_table", "error({})", r"{at}.*raised a table as its error"),
    ("stop_when_runtime_error", "return s:particle(99999).position[1] > 0", r"{at}.*99999"),
    ("stop_when_calls_run", "s:run { steps = 1 }; return false", r"{at}.*run"),
]:
    case(name, "stop_when: " + name.replace("stop_when_", "").replace("_", " "), expect,
         replace={"run": "sim:run { steps = 10, check_every = 1, stop_when = function(s)"}, after={"run": [wrong("  " + body), "end }"]})

# ---------------------------------------------------------------------------
# sim:set, sim:set_contact
# ---------------------------------------------------------------------------
for name, line, expect in [
    ("set_skin_negative", "sim:set { skin = -1 }", r"{at}.*skin"),
    ("set_time_step_nan", "sim:set { time_step = 0/0 }", r"{at}.*time_step"),
    ("set_steps_per_contact_zero", "sim:set { steps_per_contact = 0 }", r"{at}.*steps_per_contact"),
    ("set_threads_negative", "sim:set { threads = -4 }", r"{at}.*threads"),
    ("set_pruning_text", 'sim:set { pruning = "on" }', r"{at}.*pruning"),
    ("set_misspelled_key", "sim:set { skn = 1e-4 }", r"{at}.*unknown key 'skn'"),
    ("set_dimension", "sim:set { dimension = 3 }", r"{at}.*dimension"),
    ("set_contact_unknown_pair", 'sim:set_contact("glass", "sand", { friction = 0.2 })', r"{at}.*sand"),
    ("set_contact_unknown_parameter", 'sim:set_contact("glass", "glass", { frction = 0.2 })', r"{at}.*frction"),
    ("set_contact_friction_nan", 'sim:set_contact("glass", "glass", { friction = 0/0 })', r"{at}.*friction"),
    ("set_contact_restitution_two", 'sim:set_contact("glass", "glass", { restitution = 2 })', r"{at}.*restitution"),
    ("set_contact_no_table", 'sim:set_contact("glass", "glass")', r"{at}.*set_contact"),
    ("set_contact_model", 'sim:set_contact("glass", "glass", { model = "hertz_mindlin" })', r"{at}.*model"),
]:
    case(name, name.replace("_", " "), expect, after={"output": [wrong(line)]})
case("set_time_step_above_limit", "sim:set gives a time step far above the stability limit",
     r"time_step 0\.001 s is above the stability limit", after={"output": [wrong("sim:set { time_step = 1e-3 }")]})

# ---------------------------------------------------------------------------
# diagnostics
# ---------------------------------------------------------------------------
for name, line, expect in [
    ("diagnostic_unknown", 'sim:diagnostic("pressure_probe", {})', r"{at}.*pressure_probe"),
    ("diagnostic_name_number", "sim:diagnostic(3, {})", r"{at}.*diagnostic"),
    ("diagnostic_wall_force_unknown_wall", 'sim:diagnostic("wall_force", { wall = "lid" })', r"diagnostic_wall_force_unknown_wall\.lua:\d+:.*wall_force.*'lid'"),
    ("diagnostic_wall_force_no_wall", 'sim:diagnostic("wall_force", {})', r"{at}.*wall"),
    ("diagnostic_wall_force_window_negative", 'sim:diagnostic("wall_force", { wall = "drum", window = -1 })', r"{at}.*window"),
    ("diagnostic_wall_force_window_nan", 'sim:diagnostic("wall_force", { wall = "drum", window = 0/0 })', r"{at}.*window"),
    ("diagnostic_unknown_option", 'sim:diagnostic("wall_force", { wall = "drum", widnow = 1e-3 })', r"{at}.*unknown option 'widnow'"),
    ("diagnostic_zones_zero", 'sim:diagnostic("zones", { zones = 0 })', r"{at}.*zones"),
    ("diagnostic_zones_text", 'sim:diagnostic("zones", { zones = "seven" })', r"{at}.*'zones' must be a number, got the text 'seven'"),
    ("diagnostic_zones_list", 'sim:diagnostic("zones", { zones = { 1, 2 } })', r"{at}.*'zones' must be a number, got a list"),
    ("diagnostic_zones_misspelled", 'sim:diagnostic("zones", { zone = 7 })', r"{at}.*unknown option 'zone' \(did you mean 'zones'\?\)"),
    ("diagnostic_zones_every_zero", 'sim:diagnostic("zones", { every = 0 })', r"{at}.*every"),
    ("diagnostic_peaks_force_max_negative", 'sim:diagnostic("contact_peaks", { force_max = -1 })', r"{at}.*force_max"),
    ("diagnostic_options_not_table", 'sim:diagnostic("wall_force", "drum")', r"{at}.*(table|option)"),
    ("diagnostic_results_unknown_id", "sim:diagnostic_results(999)", r"{at}.*999"),
    ("diagnostic_results_id_past_int", "sim:diagnostic_results(2^32 + 1)", r"{at}.*no diagnostic with id 4294967297"),
    ("remove_diagnostic_unknown_id", "sim:remove_diagnostic(999)", r"{at}.*999"),
]:
    case(name, name.replace("_", " "), expect, after={"output": [wrong(line)]})

case("diagnostic_label_taken", "two diagnostics under one label: their rows would mix",
     r"{at}.*label 'zones' is taken by diagnostic 'zones'",
     after={"output": ['sim:diagnostic("zones", {})', wrong('sim:diagnostic("zones", { mean = "cartesian" })')]})

case("diagnostic_label_reused", "a label back after remove_diagnostic with other options",
     r"{at}.*label 'zones' was used in this output by a removed diagnostic with other options",
     after={"output": ['sim:remove_diagnostic(sim:diagnostic("zones", {}))',
                       wrong('sim:diagnostic("zones", { mean = "cartesian" })')]})
case("diagnostic_label_reused_late_output", "a label back with other options, the output opened after the first",
     r"{at}.*label 'zones' was used in this output by a removed diagnostic with other options",
     before={"output": ['local first = sim:diagnostic("zones", {})']},
     after={"output": ["sim:remove_diagnostic(first)", wrong('sim:diagnostic("zones", { mean = "cartesian" })')]})
case("contact_histories_into_open_output", "contact histories saved into the run's own output, still open",
     r"{at}.*still open by its run",
     replace={"output": 'sim:output { file = "open_output.h5" }'},
     after={"run": [wrong('sim:save_contact_histories { file = "open_output.h5", material = "glass" }')]})
case("result_name_slash", "a result name with a '/' (a column of /results)",
     r"{at}.*result: the name 'a/b' cannot name a column of /results",
     after={"output": [wrong('sim:result { ["a/b"] = 1 }')]})
case("result_name_comma", "a result name with a ',' (it would split in a sweep's lists of names)",
     r"{at}.*result: the name 'x,y' cannot name a column of /results",
     after={"output": [wrong('sim:result { ["x,y"] = 1 }')]})
case("set_position_outside_wall", "set_position puts a particle outside the drum",
     r"{at}.*would lie outside wall 'drum'",
     after={"output": [wrong("sim:set_position(sim:particles()[1], { 0.05, 0 })")]})

# ---------------------------------------------------------------------------
# picture
# ---------------------------------------------------------------------------
for name, line, expect in [
    ("picture_no_file", "sim:picture { width = 100 }", r"{at}.*file"),
    ("picture_jpeg", 'sim:picture { file = "p.jpg" }', r"{at}.*(png|svg|p\.jpg)"),
    ("picture_width_zero", 'sim:picture { file = "p.png", width = 0 }', r"{at}.*width"),
    ("picture_width_huge", 'sim:picture { file = "p.png", width = 1e9 }', r"{at}.*width"),
    ("picture_height_negative", 'sim:picture { file = "p.png", height = -10 }', r"{at}.*height"),
    ("picture_height_huge", 'sim:picture { file = "p.png", width = 100, height = 1e9 }', r"{at}.*height"),
    ("picture_color_by_unknown", 'sim:picture { file = "p.png", color_by = "colour" }', r"{at}.*colour"),
    ("picture_range_short", 'sim:picture { file = "p.png", range = { 1 } }', r"{at}.*range"),
    ("picture_range_nan", 'sim:picture { file = "p.png", range = { 0/0, 1 } }', r"{at}.*range"),
    ("picture_range_reversed", 'sim:picture { file = "p.png", range = { 2, 1 } }', r"{at}.*range"),
    ("picture_view_reversed", 'sim:picture { file = "p.png", view = { lo = { 1, 1 }, hi = { 0, 0 } } }', r"{at}.*view"),
    ("picture_view_nan", 'sim:picture { file = "p.png", view = { lo = { 0/0, 0 }, hi = { 1, 1 } } }', r"{at}.*view"),
    ("picture_view_empty", 'sim:picture { file = "p.png", view = { lo = { 0, 0 }, hi = { 0, 0 } } }', r"{at}.*view"),
    ("picture_misspelled_key", 'sim:picture { file = "p.png", colour_by = "speed" }', r"{at}.*unknown key 'colour_by'"),
    ("picture_missing_dir", 'sim:picture { file = "no/such/dir/p.png" }', r"{at}.*no/such/dir"),
]:
    case(name, name.replace("_", " "), expect, after={"run": [wrong(line)]})

# ---------------------------------------------------------------------------
# the agglomerate library (lua/granule/agglomerate.lua)
# ---------------------------------------------------------------------------
AGG_HEAD = 'local agglomerate = require "granule.agglomerate"'
for name, line, expect in [
    ("agglomerate_unknown_option", "agglomerate.prepare(sim, { count = 10, surface_enrgy = 1 })", r"{at}.*unknown option 'surface_enrgy'"),
    ("agglomerate_count_zero", "agglomerate.prepare(sim, { count = 0 })", r"{at}.*count"),
    ("agglomerate_seed_fraction", "agglomerate.prepare(sim, { count = 10, seed = 1.5 })", r"{at}.*seed"),
    ("agglomerate_density_nan", "agglomerate.prepare(sim, { count = 10, density = 0/0 })", r"{at}.*density"),
    ("agglomerate_size_spread_one", "agglomerate.size_classes(5e-6, 1, 7)", r"{at}.*size_spread"),
    ("agglomerate_size_classes_zero", "agglomerate.size_classes(5e-6, 0.05, 0)", r"{at}.*size_classes"),
    ("agglomerate_region_too_small", "agglomerate.random_positions(2, { 0, 0 }, 1e-6, { 1e-6, 1e-6, 1e-6, 1e-6, 1e-6 }, 0)", r"{at}.*(generation_diameter|small)"),
    ("agglomerate_options_not_table", 'agglomerate.prepare(sim, "small")', r"{at}.*(option|table)"),
]:
    case(name, "agglomerate helper: " + name.replace("agglomerate_", "").replace("_", " "), expect,
         before={"sim": [AGG_HEAD]}, replace={"sim": "local sim = simulation { dimension = 2, record_contacts = true }"},
         drop=["material", "wall_material", "contact", "wall_contact", "wall", "fill", "output", "run"],
         after={"sim": [wrong(line)]})
case("agglomerate_with_particles", "agglomerate.prepare on a simulation that already holds particles",
     r"{at}.*no particles", before={"sim": [AGG_HEAD]}, after={"run": [wrong("agglomerate.prepare(sim, { count = 10 })")]})

# ---------------------------------------------------------------------------
# parameters { } and -D
# ---------------------------------------------------------------------------
P = "local p = parameters { %s }"
for name, text, args, expect in [
    ("param_minus_d_text_for_number", "count = 5", "-D count=five", r"count"),
    ("param_minus_d_nan", "count = 5", "-D count=nan", r"count"),
    ("param_minus_d_inf", "count = 5", "-D count=1e999", r"count"),
    ("param_minus_d_bad_boolean", "overlap = true", "-D overlap=maybe", r"overlap"),
    ("param_minus_d_unknown", "count = 5", "-D cuont=6", r"cuont"),
    ("param_minus_d_empty", "count = 5", "-D count=", r"count"),
    ("param_minus_d_fraction_count", "count = 5", "-D count=2.5", r"{at}.*count"),
    ("param_minus_d_negative_count", "count = 5", "-D count=-3", r"{at}.*count"),
    ("param_minus_d_outside_range", "count = { default = 5, integer = true, min = 1, max = 1000 }",
     "-D count=1e300", r"-D count=1e300: 'count' must be a whole number >= 1 and <= 1000"),
    ("param_minus_d_below_exclusive", "count = { default = 5, above = 0 }", "-D count=0",
     r"-D count=0: 'count' must be > 0"),
]:
    fill = FILL % ('count = p.count, radius = 3e-4, material = "glass"' if "overlap" not in text
                   else 'count = 5, radius = 3e-4, material = "glass", overlap = p.overlap')
    case(name, f"-D value of the wrong kind ({args})", expect, args=args,
         before={"sim": [P % text]}, replace={"fill": wrong(fill)})
case("rolling_damping_with_constant", "rolling_damping given to the constant rolling torque, which has no dashpot",
     r"{at}.*rolling_damping = 0.3 acts only with rolling_model", replace={"contact": wrong('sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3, rolling_friction = 0.1, rolling_model = "constant", rolling_damping = 0.3 }')})
case("twisting_in_2d", "twisting_friction in a 2D scene, whose spins (about z) never twist a contact",
     r"{at}.*twisting_friction = 0.1 acts about the contact normal.*3D only", replace={"contact": wrong('sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3, twisting_friction = 0.1 }')})
case("rolling_model_without_friction", "rolling_model given with neither rolling_friction nor twisting_friction (it would do nothing)",
     r"{at}.*act only with rolling_friction > 0 or twisting_friction > 0", base=BASE3,
     replace={"contact": wrong('sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.8, friction = 0.3, rolling_model = "constant" }')})
case("central_strength_without_field", "sim:set_central_strength where the scene has no central field (it would change nothing)",
     r"{at}.*no central field", after={"fill": [wrong("sim:set_central_strength(2)")]})
case("param_minus_d_without_parameters", "-D given to a scene that declares no parameters{...}: refused at its run, before any step",
     r"{at}.*-D count given, but the scene declares no parameters", args="-D count=6", replace={"run": wrong("sim:run { steps = 10 }")})
for name, text, expect in [
    ("param_default_function", "count = function() return 5 end", r"{at}.*count"),
    ("param_default_nil_table", "count = { unit = 'm' }", r"{at}.*count"),
    ("param_misspelled_field", "count = { default = 5, unti = '-' }", r"{at}.*unti"),
    ("param_default_nan", "count = 0/0", r"{at}.*count"),
    ("param_default_outside_range", "count = { default = 0, min = 1 }", r"{at}.*'count' has a default 0 that is not >= 1"),
    ("param_range_on_text", "mode = { default = 'fast', min = 1 }", r"{at}.*'mode' has a range .* not a number"),
    ("param_not_a_table", '"count"', r"{at}.*parameters"),
    ("param_name_number", "[1] = 5", r"{at}.*(name|parameter)"),
]:
    case(name, "parameters { " + text + " }: a bad declaration", expect, before={"sim": [wrong(P % text)]})
case("param_declared_twice", "parameters { } called twice",
     r"{at}.*parameters", before={"sim": [P % "count = 5", wrong(P.replace("local p", "local q") % "speed = 1")]})
case("param_write_read_only", "assigning into the read-only parameter table",
     r"{at}.*read-only", before={"sim": [P % "count = 5", wrong("p.count = 6")]})

# ---------------------------------------------------------------------------
# one file, one role; a run that outpaces its time step; a region already full
# ---------------------------------------------------------------------------
case("output_twice", "sim:output called again on the file it already writes (it would be emptied)",
     r"{at}.*already opened by this simulation", after={"output": [wrong("sim:output {}")]})
case("checkpoint_over_output", "checkpoints into the run's output file (run with -o out.h5)",
     r"{at}.*this simulation's output", after={"output": [wrong('sim:checkpoint { file = "out.h5", every_steps = 5 }')]})
case("close_in_callback", "the output closed from inside a run's callback",
     r"{at}.*close: not from inside a run's callback",
     after={"output": [wrong("sim:every { steps = 2, function(s) s:close() end }")]})
case("output_in_callback", "an output opened from inside a run's callback",
     r"{at}.*output: not from inside a run's callback",
     after={"output": [wrong('sim:every { steps = 2, function(s) s:output { file = "other.h5" } end }')]})
case("particle_steps_over", "a particle at 1e4 m/s moves farther in one step than its radius",
     r"particle 5 moves .* more than the smallest radius",
     after={"fill": [wrong('sim:add_particle { position = { 0, 0 }, radius = 3e-4, material = "glass", velocity = { 1e4, 0 } }')]})
case("walton_braun_restitution_underflow", "restitution 1e-300: K2 = K1 / e^2 overflows",
     r"{at}.*restitution = 1e-300 makes the unloading stiffness K2 = K1 / e\^2 \(Eq. 3.1\) overflow",
     replace={"contact": wrong('sim:contact { "glass", "glass", model = "walton_braun", k_load = 1e4, restitution = 1e-300, friction = 0.3 }')})
case("wall_steps_over", "a wall at 1e4 m/s moves farther in one step than the smallest radius",
     r"wall 'floor' moves .* more than the smallest free particle's radius", base=BASE3,
     replace={"wall": wrong('sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, velocity = { 0, 0, 1e4 }, material = "steel" }')})
case("schedule_twice", "a second schedule of one target: it would overwrite the first at every step",
     r"{at}.*schedule 1 already sets it for 'glass'-'glass'",
     after={"output": ['sim:schedule { "friction", from = "glass", to = "glass", linear = { 0, 0.1, 1, 0.3 } }',
                       wrong('sim:schedule { "friction", from = "glass", to = "glass", linear = { 0, 0.5, 1, 0.9 } }')]})
case("schedule_switch_ramp", "a ramp of a switch (allow_tension is 0 or 1)",
     r"{at}.*'allow_tension' is a switch \(0 or 1\): a schedule of it may only jump",
     after={"output": [wrong('sim:schedule { "allow_tension", from = "glass", to = "glass", linear = { 0, 1, 1, 0 } }')]})
case("schedule_switch_half", "a schedule holding a switch at 0.5 (neither 0 nor 1; no ramp)",
     r"{at}.*'allow_tension' is a switch: its values are 0 or 1, not 0.5",
     after={"output": [wrong('sim:schedule { "allow_tension", from = "glass", to = "glass", constant = 0.5 }')]})
case("contact_switch_fraction", "a switch given a value between 0 and 1",
     r"{at}.*'allow_tension' = 0.5 is a switch: give 0 or 1",
     replace={"contact": wrong('sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3, allow_tension = 0.5 }')})
case("threads_past_int", "threads = 2^32 + 3 (it must not wrap to 3)",
     r"{at}.*threads must be from 0 to 4096.*got 4294967299",
     replace={"sim": wrong('local sim = simulation { dimension = 2, threads = 2^32 + 3 }')})
case("diagnostic_zones_past_int", "zones = 2^32 + 3 (it must not wrap to 3)",
     r"{at}.*'zones' must be an integer from 1 to 1000",
     after={"output": [wrong('sim:diagnostic("zones", { zones = 2^32 + 3 })')]})
case("checkpoint_no_folder", "checkpoints into a folder that does not exist (found at the first signal otherwise)",
     r"{at}.*the folder no_such_folder does not exist",
     after={"output": [wrong('sim:checkpoint { file = "no_such_folder/x.chk.h5", every_steps = 5 }')]})
case("result_without_name", "sim:result given a value without a name",
     r"{at}.*every value needs a name", after={"output": [wrong("sim:result { 5 }")]})
case("particle_radius_huge", "a particle of radius 1e300 m: its mass overflows",
     r"{at}.*not finite positive", after={"fill": [wrong('sim:add_particle { position = { 0, 0 }, radius = 1e300, material = "glass" }')]})
case("fill_region_full", "a fill without overlaps asking for far more particles than the region holds",
     r"{at}.*would take 236 of the region's volume", base=BASE3,
     replace={"fill": wrong('sim:fill { region = { box = { lo = { -0.002, -0.002, 0.001 }, hi = { 0.002, 0.002, 0.004 } } }, count = 100000, radius = 3e-4, material = "glass", seed = 2, overlap = false }')})
case("fill_region_jammed", "a fill without overlaps asking for half the region's volume: random placement jams first",
     r"{at}.*placed only .* the region is too full for particles that may not overlap", base=BASE3,
     replace={"fill": wrong('sim:fill { region = { box = { lo = { -0.002, -0.002, 0.001 }, hi = { 0.002, 0.002, 0.004 } } }, count = 212, radius = 3e-4, material = "glass", seed = 2, overlap = false }')})


def main():
    os.makedirs(OUT, exist_ok=True)
    names = set()
    for old in os.listdir(OUT):
        if old.endswith(".lua"):
            os.remove(os.path.join(OUT, old))
    for c in CASES:
        if c["name"] in names:
            sys.exit("two cases named " + c["name"])
        names.add(c["name"])
        with open(os.path.join(OUT, c["name"] + ".lua"), "w") as f:
            f.write(build(c))
    print(f"wrote {len(CASES)} scenes to {OUT}")


if __name__ == "__main__":
    main()
