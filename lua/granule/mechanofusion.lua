-- granule.mechanofusion: the Mechanofusion system of dissertation chapters
-- 4-5 and appendix A as a reusable builder. Table 4.1 defaults, the geometry
-- choices of SPEC 4.1, and every number a parameter.
--
--   local mf = require "granule.mechanofusion"
--   local p = parameters(mf.parameter_spec { duration = { default = 0.05, unit = "s" } })
--   local sim, geo = mf.build(p)
--   local ids = mf.attach_diagnostics(sim, geo, p)
--   sim:run { duration = p.duration }
--   local summary = mf.summary(sim, geo, ids)
--
-- Geometry (SPEC 4.1): the chamber is a circle of radius R about the origin
-- turning counter-clockwise at omega; the stationary inner piece of radius
-- r_i sits at angle `inner_angle` with its centre at R - gap - r_i from the
-- origin, so the narrowest gap is `gap`; the scraper is a straight row of
-- fixed particles of the powder's size touching the chamber wall at
-- `scraper_angle` degrees downstream of the inner piece, leaning into the flow
-- at `scraper_tilt` to the wall's tangent, `scraper_length` long.
-- size_scale = s multiplies every length of the machine (not the particles)
-- and the loading by s^2 (the double-sized system of 5.3.2: s = 2).
-- dimension = 3 extrudes the section `slab_layers` diameters along z with a
-- periodic axis and slab_layers times the particles (appendix A).
local granule = require "granule"
local checks = require "granule.checks"

local M = {}

--- The parameters of the base case (Table 4.1, SPEC 4.1), in the form
--- `parameters {}` takes: name = { default =, unit =, doc = }.
M.defaults = {
  dimension = { default = 2, unit = "-", doc = "2 (the dissertation's runs) or 3 (periodic slab, app. A)" },
  particles = { default = 1500, unit = "-", doc = "loading of the 2D section at size_scale 1 (Table 4.1)" },
  radius = { default = 0.2e-3, unit = "m", doc = "particle radius (Table 4.1)" },
  density = { default = 1200, unit = "kg/m^3", doc = "particle density (Table 4.1)" },
  chamber_radius = { default = 12.5e-3, unit = "m", doc = "chamber radius R (25 mm diameter)" },
  inner_radius = { default = 5e-3, unit = "m", doc = "inner piece radius (10 mm diameter)" },
  gap = { default = 1.6e-3, unit = "m", doc = "narrowest gap H between inner piece and chamber" },
  inner_angle = { default = 0, unit = "deg", doc = "direction of the inner piece's centre" },
  inner_shape = { default = "cylinder", doc = "the inner piece as 'cylinder' (an analytic wall); in 2D 'polyline' (the same circle drawn as four arcs: sim:wall_polyline, where a real profile can go); in 3D 'mesh' (a prism of inner_facets faces: sim:wall_mesh, where a CAD file can go)" },
  inner_facets = { default = 180, unit = "-", doc = "inner_shape = 'mesh': flat faces around the inner piece" },
  scraper_shape = { default = "particles", doc = "the scraper as 'particles' (a row of fixed particles, 4.2.1) or a blade one particle diameter thick over the same row, its tip rounded: in 2D 'polyline' (sim:wall_polyline), in 3D 'mesh' (sim:wall_mesh, square-ended)" },
  rpm = { default = 2000, unit = "1/min", doc = "chamber speed (counter-clockwise)" },
  k_load = { default = 20000, unit = "N/m", doc = "Walton-Braun loading stiffness K1" },
  restitution = { default = 0.85, unit = "-", doc = "coefficient of restitution e" },
  friction_particle = { default = 0.4, unit = "-", doc = "particle-particle friction" },
  friction_wall = { default = 0.5, unit = "-", doc = "particle-wall (and scraper) friction" },
  steps_per_contact = { default = 40, unit = "-", doc = "n of Eq. 4.1" },
  scraper = { default = true, doc = "add the scraper (a row of fixed particles)" },
  scraper_angle = { default = 100, unit = "deg", doc = "scraper position downstream of the inner piece" },
  scraper_tilt = { default = 70, unit = "deg", doc = "scraper angle to the wall's tangent (70: no particle jams in the wedge with the wall; 40, SPEC 4.1, jams one: docs/mechanofusion.md)" },
  scraper_length = { default = 4.4e-3, unit = "m", doc = "scraper length (at size_scale 1)" },
  scraper_wall_overlap = { default = 0, unit = "m", doc = "sink the scraper row into the wall this far (0: touching, SPEC 4.1)" },
  size_scale = { default = 1, unit = "-", doc = "machine lengths x s, loading x s^2 (5.3.2: 2)" },
  slab_layers = { default = 4, unit = "-", doc = "3D slab depth in particle diameters (app. A: 4)" },
  seed = { default = 1, unit = "-", doc = "random seed of the fill" },
  max_speed = { default = 0.01, unit = "m/s", doc = "largest random initial speed (zero net momentum)" },
  area_inner_from = { default = -45, unit = "deg", doc = "inner-piece area starts (from the inner piece)" },
  area_scraper_from = { default = 45, unit = "deg", doc = "scraper area starts, inner-piece area ends" },
  area_free_from = { default = 150, unit = "deg", doc = "free-diffusion area starts, scraper area ends" },
  area_input_from = { default = 250, unit = "deg", doc = "input area starts, free diffusion ends" },
  zones = { default = 7, unit = "-", doc = "radial zones of equal volume (4.2.3)" },
  gap_sector = { default = 10, unit = "deg", doc = "half-width of the gap_profile sector about the inner piece (Eqs. 5.4, 5.6)" },
  gap_bins = { default = 8, unit = "-", doc = "bins across the gap of the gap_profile diagnostic" },
  window = { default = 0.01, unit = "s", doc = "averaging window of the diagnostics' series" },
  every = { default = 10, unit = "-", doc = "steps between diagnostic samples" },
}

--- mf.parameter_spec(extra) -> the defaults plus a scene's own parameters
--- (an extra entry with the same name replaces the default's).
function M.parameter_spec(extra)
  local spec = {}
  for k, v in pairs(M.defaults) do spec[k] = v end
  for k, v in pairs(extra or {}) do spec[k] = v end
  return spec
end

-- Values with the defaults filled in and checked, so build() also works from
-- a plain table (tests, other scenes).
local function complete(p)
  local where = "mechanofusion.build"
  local v = {}
  for k, d in pairs(M.defaults) do
    if p[k] == nil then v[k] = d.default else v[k] = p[k] end
  end
  if v.dimension ~= 2 and v.dimension ~= 3 then checks.fail(where, "dimension", "2 or 3", v.dimension) end
  for _, k in ipairs { "particles", "radius", "density", "chamber_radius", "inner_radius", "gap", "k_load",
                       "restitution", "size_scale", "steps_per_contact", "slab_layers", "zones",
                       "window", "every", "gap_sector", "gap_bins" } do
    checks.positive(where, k, v[k], M.defaults[k].unit)
  end
  for _, k in ipairs { "rpm", "friction_particle", "friction_wall", "scraper_length",
                       "max_speed", "scraper_wall_overlap" } do
    checks.non_negative(where, k, v[k], M.defaults[k].unit)
  end
  if v.restitution > 1 then checks.fail(where, "restitution", "in (0, 1]", v.restitution) end
  if v.particles ~= math.floor(v.particles) then checks.fail(where, "particles", "a whole number", v.particles) end
  if v.slab_layers ~= math.floor(v.slab_layers) then checks.fail(where, "slab_layers", "a whole number", v.slab_layers) end
  if type(v.scraper) ~= "boolean" then checks.fail(where, "scraper", "true or false", v.scraper) end
  if v.inner_shape ~= "cylinder" and not (v.inner_shape == "polyline" and v.dimension == 2)
      and not (v.inner_shape == "mesh" and v.dimension == 3) then
    checks.fail(where, "inner_shape", "'cylinder', 'polyline' in 2D or 'mesh' in 3D", v.inner_shape)
  end
  if v.scraper_shape ~= "particles" and not (v.scraper_shape == "mesh" and v.dimension == 3)
      and not (v.scraper_shape == "polyline" and v.dimension == 2) then
    checks.fail(where, "scraper_shape", "'particles', 'polyline' in 2D or 'mesh' in 3D", v.scraper_shape)
  end
  if v.inner_facets ~= math.floor(v.inner_facets) or v.inner_facets < 12 then
    checks.fail(where, "inner_facets", "a whole number >= 12", v.inner_facets)
  end
  local s = v.size_scale
  if v.inner_radius * s + v.gap * s >= v.chamber_radius * s then
    checks.raise(string.format("%s: inner_radius + gap (%g m) must be below chamber_radius (%g m)",
      where, (v.inner_radius + v.gap) * s, v.chamber_radius * s))
  end
  if v.gap * s < 2 * v.radius then
    checks.raise(string.format("%s: gap %g m is narrower than one particle (%g m)", where, v.gap * s, 2 * v.radius))
  end
  if v.scraper_wall_overlap > 2 * v.radius then
    checks.fail(where, "scraper_wall_overlap", "at most one particle diameter", v.scraper_wall_overlap)
  end
  if not (v.scraper_tilt > 0 and v.scraper_tilt < 90) then
    checks.fail(where, "scraper_tilt", "in (0, 90) degrees", v.scraper_tilt)
  end
  local a = { v.area_inner_from, v.area_scraper_from, v.area_free_from, v.area_input_from, v.area_inner_from + 360 }
  for k = 1, 4 do
    if not (a[k + 1] > a[k]) then
      checks.raise(string.format("%s: the area bounds must increase: area_inner_from < area_scraper_from "
        .. "< area_free_from < area_input_from < area_inner_from + 360 (got %g, %g, %g, %g)", where,
        a[1], a[2], a[3], a[4]))
    end
  end
  return v
end

--- mf.geometry(p) -> the derived geometry (no simulation): scaled lengths,
--- the particle count, the inner piece's centre, the scraper's particle
--- positions, the slab depth, the area sectors.
function M.geometry(p)
  local v = complete(p)
  local s = v.size_scale
  local g = { dimension = v.dimension, radius = v.radius, omega = granule.rpm(v.rpm), rpm = v.rpm,
              chamber_radius = v.chamber_radius * s, inner_radius = v.inner_radius * s, gap = v.gap * s,
              scraper = v.scraper, values = v }
  g.inner_offset = g.chamber_radius - g.gap - g.inner_radius           -- SPEC 4.1: 5.9 mm
  local phi0 = math.rad(v.inner_angle)
  g.inner_center = granule.vec.polar(phi0, g.inner_offset)
  g.layers = v.dimension == 3 and v.slab_layers or 1
  g.depth = 2 * v.radius * g.layers                                    -- 3D: slab; 2D: one diameter
  g.particles = math.floor(v.particles * s * s * g.layers + 0.5)
  -- The scraper: a row touching the wall (zero clearance) at scraper_angle
  -- downstream, leaning inward and upstream so the flow meets its face.
  g.scraper_positions = {}
  if v.scraper then
    local phi = phi0 + math.rad(v.scraper_angle)
    local outward = granule.vec.polar(phi)
    local tangent = granule.vec.polar(phi + math.pi / 2)   -- the wall's motion there
    -- Touching the wall; sunk into it by scraper_wall_overlap, which opens the
    -- acute cusp between wall and first particle (a radius makes it square).
    local first = granule.vec.scale(outward, g.chamber_radius - v.radius + v.scraper_wall_overlap)
    local tilt = math.rad(v.scraper_tilt)
    local direction = granule.vec.add(granule.vec.scale(outward, -math.sin(tilt)),
                                      granule.vec.scale(tangent, -math.cos(tilt)))
    local count = math.max(1, math.floor(v.scraper_length * s / (2 * v.radius) + 0.5))
    g.scraper_positions = granule.particle_row(first, direction, count, v.radius)
    g.scraper_first, g.scraper_direction, g.scraper_count = first, direction, count
  end
  g.areas = {
    area_inner_piece = { v.area_inner_from, v.area_scraper_from },
    area_scraper = { v.area_scraper_from, v.area_free_from },
    area_free_diffusion = { v.area_free_from, v.area_input_from },
    area_input = { v.area_input_from, v.area_inner_from + 360 },
  }
  return g
end

--- mf.build(p) -> sim, geo: the simulation with materials, Walton-Braun
--- contacts, chamber, inner piece, scraper and the random fill (SPEC 2: may
--- overlap each other, never walls or the scraper; small random velocities
--- with zero net momentum). Nothing is run.
function M.build(p)
  local g = M.geometry(p)
  local v = g.values
  local sim
  if g.dimension == 3 then
    sim = simulation { dimension = 3, steps_per_contact = v.steps_per_contact,
                       periodic = { axis = "z", origin = 0, length = g.depth } }
  else
    sim = simulation { dimension = 2, steps_per_contact = v.steps_per_contact }
  end
  sim:material { name = "powder", density = v.density }
  sim:material { name = "steel", density = 7800 }
  sim:contact { "powder", "powder", model = "walton_braun", k_load = v.k_load,
                restitution = v.restitution, friction = v.friction_particle }
  sim:contact { "powder", "steel", model = "walton_braun", k_load = v.k_load,
                restitution = v.restitution, friction = v.friction_wall }
  -- The scraper is powder-sized fixed particles (4.2.1), with the wall's friction.
  sim:material { name = "scraper", density = v.density }
  sim:contact { "powder", "scraper", model = "walton_braun", k_load = v.k_load,
                restitution = v.restitution, friction = v.friction_wall }
  local function at(xy, z) if g.dimension == 3 then return { xy[1], xy[2], z } end return xy end
  sim:wall_cylinder { name = "chamber", center = at({ 0, 0 }, 0), radius = g.chamber_radius, inside = true,
                      angular_velocity = g.omega, material = "steel" }
  if v.inner_shape == "polyline" then
    -- Counter-clockwise through four points on the circle, each quarter an
    -- arc bulging outwards (to the right of its direction: radius < 0).
    local c, ri, points, arcs = g.inner_center, g.inner_radius, {}, {}
    for k = 1, 4 do
      local a = (k - 1) * math.pi / 2
      points[k] = { c[1] + ri * math.cos(a), c[2] + ri * math.sin(a) }
      arcs[k] = { segment = k, radius = -ri }
    end
    sim:wall_polyline { name = "inner_piece", points = points, closed = true, solid = true, arcs = arcs,
                        axis_point = c, material = "steel" }
  elseif v.inner_shape == "mesh" then
    -- A prism inscribed in the circle (R (1 - cos(pi/N)) inside it at each face's middle:
    -- 0.8 um for N = 180), reaching two radii past the periodic slab at both ends, so no
    -- particle meets its open rims.
    local shapes = require "granule.mesh_shapes"
    local path = shapes.prism { center = g.inner_center, radius = g.inner_radius, facets = v.inner_facets,
                                z_min = -2 * v.radius, z_max = g.depth + 2 * v.radius }
    sim:wall_mesh { name = "inner_piece", file = path, material = "steel",
                    axis_point = at(g.inner_center, 0) }
    os.remove(path)
  else
    sim:wall_cylinder { name = "inner_piece", center = at(g.inner_center, 0), radius = g.inner_radius,
                        inside = false, material = "steel" }
  end
  g.scraper_ids = {}
  if v.scraper and v.scraper_shape == "mesh" then
    -- The blade the particle row stands for: one diameter thick, from the first
    -- particle's back to the last one's front, across the slab and two radii past it.
    local shapes = require "granule.mesh_shapes"
    local d, r = g.scraper_direction, v.radius
    local across = { -d[2], d[1] }
    local corner = granule.vec.sub(g.scraper_first, granule.vec.add(granule.vec.scale(d, r),
                                                                     granule.vec.scale(across, r)))
    local length = 2 * r * g.scraper_count
    local path = shapes.box { corner = { corner[1], corner[2], -2 * r },
                              edges = { { d[1] * length, d[2] * length, 0 }, { across[1] * 2 * r, across[2] * 2 * r, 0 },
                                        { 0, 0, g.depth + 4 * r } } }
    sim:wall_mesh { name = "scraper", file = path, material = "steel" }
    os.remove(path)
  end
  if v.scraper and v.scraper_shape == "polyline" then
    -- The row's outline: from the first particle's centre to the last one's, one
    -- diameter wide, both ends half circles of the particles' radius (so a particle
    -- meets the tip as it meets the row's last particle). Closed and solid.
    local d, r = g.scraper_direction, v.radius
    local across = { -d[2], d[1] }
    local first = g.scraper_first
    local last = granule.vec.add(first, granule.vec.scale(d, 2 * r * (g.scraper_count - 1)))
    local function off(x, k) return granule.vec.add(x, granule.vec.scale(across, k * r)) end
    local points = { off(first, -1), off(last, -1), off(last, 1), off(first, 1) }
    -- Segments 2 and 4 are the ends, half circles bulging outwards (to the right of
    -- their direction as the outline runs counter-clockwise: radius < 0).
    sim:wall_polyline { name = "scraper", points = points, closed = true, solid = true,
                        arcs = { { segment = 2, radius = -r }, { segment = 4, radius = -r } }, material = "steel" }
  end
  for layer = 1, v.scraper_shape == "particles" and g.layers or 0 do
    local z = (2 * layer - 1) * v.radius
    for _, x in ipairs(g.scraper_positions) do
      g.scraper_ids[#g.scraper_ids + 1] =
        sim:add_particle { position = at(x, z), radius = v.radius, material = "scraper", fixed = true }
    end
  end
  if g.particles > 0 then
    local region
    if g.dimension == 3 then
      region = { cylinder = { center = { 0, 0, 0 }, radius = g.chamber_radius, z_min = 0, z_max = g.depth } }
    else
      region = { circle = { center = { 0, 0 }, radius = g.chamber_radius } }
    end
    g.particle_ids = sim:fill { region = region, count = g.particles, radius = v.radius, material = "powder",
                                seed = v.seed, max_speed = v.max_speed }
    if v.inner_shape == "mesh" then
      -- fill{} keeps particles off a mesh's faces, not out of what they enclose:
      -- those drawn inside the inner piece are drawn again elsewhere.
      local function inside(id)
        local x = sim:particle(id).position
        local dx, dy = x[1] - g.inner_center[1], x[2] - g.inner_center[2]
        return dx * dx + dy * dy < g.inner_radius ^ 2
      end
      for round = 1, 50 do
        local kept, missing = {}, 0
        for _, id in ipairs(g.particle_ids) do
          if inside(id) then sim:remove_particle(id) missing = missing + 1 else kept[#kept + 1] = id end
        end
        g.particle_ids = kept
        if missing == 0 then break end
        for _, id in ipairs(sim:fill { region = region, count = missing, radius = v.radius, material = "powder",
                                       seed = v.seed + round, max_speed = v.max_speed }) do
          g.particle_ids[#g.particle_ids + 1] = id
        end
      end
    end
  else
    g.particle_ids = {}
  end
  return sim, g
end

--- mf.attach_diagnostics(sim, geo, { inner_force =, zones =, areas =, peaks =, gap =, overlaps =,
---                                   window =, every =, zones_mean =, keep_collisions = }) -> ids
--- Attaches the diagnostics of 4.3-4.5 and 7.2, the flow across the gap
--- (5.2: gap_profile over +-gap_sector degrees) and the deepest overlaps
--- (each true by default; false leaves it out and the run pays nothing for it).
function M.attach_diagnostics(sim, g, opts)
  opts = opts or {}
  local v = g.values
  local window, every = opts.window or v.window, opts.every or v.every
  local ids = {}
  local function wanted(name) return opts[name] ~= false end
  if wanted("inner_force") then
    ids.inner_force = sim:diagnostic("wall_force", { wall = "inner_piece", window = window, every = every,
                                                     label = "inner_piece_force" })
  end
  if wanted("zones") then
    ids.zones = sim:diagnostic("zones", { zones = v.zones, window = window, every = every,
                                          depth = g.dimension == 3 and g.depth or nil,
                                          mean = opts.zones_mean or "polar" })
  end
  local areas = {}
  for k, b in pairs(g.areas) do areas[k] = b end
  if wanted("areas") then
    local o = { window = window, every = every }
    for k, b in pairs(areas) do o[k] = b end
    ids.areas = sim:diagnostic("areas", o)
  end
  if wanted("gap") and v.inner_shape == "cylinder" then  -- its bins need the circle
    ids.gap = sim:diagnostic("gap_profile", { sector = v.gap_sector, bins = v.gap_bins, window = window,
                                               every = every, depth = g.dimension == 3 and g.depth or nil })
  end
  if wanted("overlaps") then
    ids.overlaps = sim:diagnostic("overlaps", { window = window, every = every })
  end
  if wanted("peaks") then
    -- Eq. 7.2's c = F_max / dv of this scene's loading spring, sqrt(m* K1) for
    -- two powder particles (m* = m/2; particles are spheres of mass 4/3 pi r^3 rho
    -- in 2D as in 3D): 0.020 N s/m for Table 4.1, and other values when K1,
    -- the radius or the density are changed, which a fixed 0.02 would misread.
    local mass = 4 / 3 * math.pi * v.radius ^ 3 * v.density
    local o = { window = window, keep_collisions = opts.keep_collisions or 0,
                force_max = opts.force_max or 0.1, velocity_max = opts.velocity_max or 5,
                bins = opts.bins or 200,
                force_per_velocity = opts.force_per_velocity or math.sqrt(mass / 2 * v.k_load) }
    for k, b in pairs(areas) do o[k] = b end
    ids.peaks = sim:diagnostic("contact_peaks", o)
  end
  return ids
end

--- mf.escaped(sim, geo, tolerance) -> the number of moving particles whose
--- centre lies farther from the axis than R - r + tolerance (default 0.1 r)
--- or inside the inner piece's radius + r - tolerance: particles that left the
--- powder's space.
function M.escaped(sim, g, tolerance)
  tolerance = tolerance or 0.1 * g.radius
  local count = 0
  for _, id in ipairs(g.particle_ids) do
    local q = sim:particle(id)
    local x, y = q.position[1], q.position[2]
    local from_axis = math.sqrt(x * x + y * y)
    local dx, dy = x - g.inner_center[1], y - g.inner_center[2]
    local from_inner = math.sqrt(dx * dx + dy * dy)
    if from_axis > g.chamber_radius - g.radius + tolerance or from_inner < g.inner_radius + g.radius - tolerance then
      count = count + 1
    end
  end
  return count
end

local area_names = { "inner_piece", "scraper", "input", "free_diffusion" }
M.area_names = area_names
--- The readings of 4.7 the contact_peaks diagnostic sums side by side.
M.coating_readings = { "one_patch_rstar", "two_patches_rstar", "one_patch_r", "two_patches_r" }

--- mf.summary(sim, geo, ids) -> a flat table of the long-time means: the
--- inner piece's normal and tangential force, per area the mean force per
--- particle and per particle-particle contact, collisions and ratios, the
--- coating time, the zones' profiles (lists, innermost first).
function M.summary(sim, g, ids)
  local out = { rpm = g.rpm, gap = g.gap, particles = g.particles, k_load = g.values.k_load,
                size_scale = g.values.size_scale, dimension = g.dimension, time = sim:time() }
  if ids.inner_force then
    local r = sim:diagnostic_results(ids.inner_force)
    out.inner_normal_force = r.mean_normal_force
    out.inner_tangential_force = r.mean_tangential_force
  end
  if ids.areas then
    local r = sim:diagnostic_results(ids.areas)
    for _, a in ipairs(area_names) do
      for _, q in ipairs { "normal_force_per_particle", "tangential_force_per_particle",
                           "normal_force_per_contact", "tangential_force_per_contact", "particles",
                           "collisions_particle", "collisions_boundary", "collision_ratio_particle",
                           "collision_ratio_boundary" } do
        out[q .. "_" .. a] = r[q .. "_" .. a]
      end
    end
  end
  if ids.peaks then
    local r = sim:diagnostic_results(ids.peaks)
    out.coating_time_estimate = r.coating_time_estimate
    out.coating_reached = r.coating_reached
    out.covered_fraction = r.covered_fraction
    -- The four readings of 4.7: patches per contact (one, two) x R (R*, r).
    for _, c in ipairs(M.coating_readings) do
      out["coating_time_" .. c] = r["coating_time_" .. c]
      out["coating_time_estimate_" .. c] = r["coating_time_estimate_" .. c]
      out["covered_fraction_" .. c] = r["covered_fraction_" .. c]
    end
    for _, threshold in ipairs { "100", "200", "1000" } do
      for _, a in ipairs(area_names) do
        out["fraction_over_" .. threshold .. "_mm_s_" .. a] = r["fraction_over_" .. threshold .. "_mm_s_" .. a]
      end
    end
    for _, a in ipairs(area_names) do
      out["mean_peak_force_" .. a] = r["mean_peak_force_" .. a]
      out["contacts_" .. a] = r["contacts_" .. a]
    end
  end
  if ids.gap then
    local r = sim:diagnostic_results(ids.gap)
    for _, q in ipairs { "shear_rate", "nominal_shear_rate", "mean_granular_temperature", "mean_solid_fraction",
                         "particles", "normal_force_per_contact", "tangential_force_per_contact", "mean_gap" } do
      out["gap_" .. q] = r[q]
    end
    out.gap_profile = {}
    for _, q in ipairs { "azimuthal_velocity", "radial_velocity", "granular_temperature", "solid_fraction",
                         "count" } do
      out.gap_profile[q] = r[q]
    end
  end
  if ids.overlaps then
    local r = sim:diagnostic_results(ids.overlaps)
    for _, k in ipairs { "particle", "fixed", "wall" } do
      out["max_overlap_ratio_" .. k] = r["max_overlap_ratio_" .. k]
    end
    out.max_overlap_ratio = r.max_overlap_ratio
    out.deepest_kind, out.deepest_time = r.deepest_kind, r.deepest_time
    out.deepest_x, out.deepest_y = r.deepest_x, r.deepest_y
  end
  if ids.zones then
    local r = sim:diagnostic_results(ids.zones)
    out.zone_volume_sum, out.chamber_volume = r.zone_volume_sum, r.chamber_volume
    out.profiles = {}
    for _, q in ipairs { "rotational_ke", "deviatoric_ke", "deviatoric_ke_cartesian", "pressure",
                         "pressure_kinetic", "pressure_virial", "collision_work_rate", "solid_fraction", "count" } do
      out.profiles[q] = r[q]
    end
  end
  return out
end

--- mf.record(sim, summary): the scalar entries of a summary into /results,
--- and the profiles as one scalar per zone (zone<k>_<quantity>, innermost
--- first) and per gap bin (gap_bin<k>_<quantity>, from the chamber wall), so
--- that a sweep's summary table holds them.
function M.record(sim, summary)
  local scalars = {}
  local function put(k, value)
    if type(value) == "number" and value == value and math.abs(value) ~= math.huge then scalars[k] = value end
  end
  for k, value in pairs(summary) do put(k, value) end
  for prefix, profile in pairs { zone = summary.profiles, gap_bin = summary.gap_profile } do
    for q, values in pairs(profile) do
      for z, value in ipairs(values) do put(string.format("%s%d_%s", prefix, z, q), value) end
    end
  end
  sim:result(scalars)
end

--- mf.picture_files({ times }, prefix) -> the picture file of each time (s):
--- <prefix>_<ms>ms.png, or <prefix>_<us>us.png for all of them when two
--- different times round to one millisecond; an error naming 'pictures' when
--- two round to one microsecond.
function M.picture_files(times, prefix)
  local function names(per_second, unit, digits)
    local files, time_of, clash = {}, {}, nil
    for k, t in ipairs(times) do
      files[k] = string.format("%s_%0" .. digits .. "d%s.png", prefix, math.floor(t * per_second + 0.5), unit)
      if time_of[files[k]] and time_of[files[k]] ~= t then clash = { time_of[files[k]], t } end
      time_of[files[k]] = t
    end
    return files, clash
  end
  local files, clash = names(1e3, "ms", 4)
  if clash then files, clash = names(1e6, "us", 7) end
  if clash then
    checks.raise(string.format("pictures: the times %.12g s and %.12g s would write one file; "
      .. "give times at least 1 us apart", clash[1], clash[2]))
  end
  return files
end

--- mf.run_with_pictures(sim, duration, { times }, prefix): runs `duration`
--- seconds, drawing the particle pattern (Figs. 4.6-4.7) at each of `times`
--- (seconds from now) into the files of mf.picture_files (<prefix>_<ms>ms.png).
function M.run_with_pictures(sim, duration, times, prefix)
  local start = sim:time()
  local files = {}
  table.sort(times)
  local names = M.picture_files(times, prefix)
  for k, t in ipairs(times) do
    if t <= duration then
      local now = sim:time() - start
      if t > now then sim:run { duration = t - now } end
      local file = names[k]
      sim:picture { file = file, width = 480, color_by = "speed" }
      files[#files + 1] = file
    end
  end
  local left = duration - (sim:time() - start)
  if left > 1e-12 then sim:run { duration = left } end
  return files
end

return M
