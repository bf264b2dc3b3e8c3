-- Stress: very stiff contacts (k_n 5e4 times the dissertation's 2e4 N/m, and a
-- Hertzian contact of steel) keep their closed forms: the automatic time step
-- follows the stiffness (Eq. 4.1), so restitution and contact time stay exact.
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local p = parameters { k_normal = { default = 1e9, unit = "N/m" } }

-- Linear spring-dashpot: e exact; t_c = pi / (omega0 sqrt(1 - zeta^2)) with omega0 = sqrt(k/m*).
local e = 0.85
local r = S.head_on { speed = 1, law = { model = "linear", k_normal = p.k_normal, restitution = e } }
S.relative(r.restitution, e, 0.01, "linear restitution at k_n = " .. p.k_normal)
local zeta = -math.log(e) / math.sqrt(math.pi ^ 2 + math.log(e) ^ 2)
local tc = math.pi / (math.sqrt(p.k_normal / (r.mass / 2)) * math.sqrt(1 - zeta ^ 2))
S.relative(r.duration, tc, 0.05, "linear contact duration")
-- Largest overlap below the undamped one, v / omega0.
S.check(r.max_overlap < 1 / math.sqrt(p.k_normal / (r.mass / 2)), "overlap %s above v/omega0", r.max_overlap)

-- Walton-Braun at the same stiffness: e = sqrt(K1/K2) (Eq. 3.4) whatever K1.
local wb = S.head_on { speed = 1, law = { model = "walton_braun", k_load = p.k_normal, restitution = e,
                                           friction = 0.4 } }
S.relative(wb.restitution, e, 0.01, "Walton-Braun restitution at K1 = " .. p.k_normal)

-- Hertz (steel, 210 GPa): elastic Thornton law, e = 1, Hertz contact time 2.868 (m*^2/(R* E*^2 v))^(1/5).
local young, poisson, speed = 210e9, 0.3, 1
local h = S.head_on { speed = speed, dimension = 3, density = 7800, young = young, poisson = poisson,
                      law = { model = "thornton_elastic", friction = 0.3 } }
S.relative(h.restitution, 1, 1e-3, "Thornton elastic restitution (steel)")
local e_star = young / (2 * (1 - poisson ^ 2))
local r_star, m_star = 0.1e-3, h.mass / 2
S.relative(h.duration, 2.868 * (m_star ^ 2 / (r_star * e_star ^ 2 * speed)) ^ 0.2, 0.05, "Hertz contact time")
print("stress.stiff_contacts ok")
