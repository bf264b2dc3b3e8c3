#!/bin/sh
# Feeds the granule command line malformed options, parameters and scenes.
# Each must be refused with a message on stderr and an exit status of 1 or 2:
# never 0, never a signal (status > 128), never silence.
#   tests/fuzz/fuzz_cli.sh build/granule SOURCE_DIR     (ctest: fuzz.cli)
set -u
granule=$1
source_dir=$2
scene="$source_dir/scenarios/binary_impact.lua"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0
count=0

refused() {  # refused DESCRIPTION [STDIN_TEXT] -- ARGS...
  what=$1
  shift
  count=$((count + 1))
  "$granule" "$@" </dev/null >out.txt 2>err.txt
  status=$?
  if [ "$status" -eq 0 ] || [ "$status" -gt 2 ] || [ ! -s err.txt ]; then
    echo "FAIL: $what: granule $* -> status $status, stderr: $(head -c 300 err.txt)"
    failures=$((failures + 1))
  fi
}

scene_file() {  # scene_file NAME CONTENT
  printf '%s\n' "$2" >"$1"
}

# ---- commands and options ----
refused "no command"
refused "unknown command" frobnicate
refused "run without a scene" run
refused "missing scene file" run no_such_scene.lua
refused "a directory as scene" run .
refused "unknown option" run "$scene" --frobnicate
refused "-o without a value" run "$scene" -o
refused "-o empty" run "$scene" -o ""
refused "-o twice" run "$scene" -o a.h5 -o b.h5
refused "-o into a missing directory" run "$scene" -o no/such/dir/out.h5 --quiet
refused "--progress without a value" run "$scene" --progress
refused "--progress zero" run "$scene" --progress 0
refused "--progress NaN" run "$scene" --progress nan
refused "--progress text" run "$scene" --progress often
refused "--help with options but no scene" repl --help -q
refused "--help with -D unknown" run "$scene" --help -D velocty=1
refused "-D without a value" run "$scene" -D
refused "-D without =" run "$scene" -D velocity
refused "-D with empty name" run "$scene" -D =1
refused "-D twice" run "$scene" -D velocity=1 -D velocity=2
refused "-D unknown parameter" run "$scene" -D velocty=1 --quiet
refused "-D NaN" run "$scene" -D velocity=nan --quiet
refused "-D inf" run "$scene" -D velocity=1e999 --quiet
refused "-D -inf" run "$scene" -D velocity=-1e999 --quiet
refused "-D text for a number" run "$scene" -D velocity=fast --quiet
refused "-D empty value for a number" run "$scene" -D velocity= --quiet
refused "-D huge" run "$scene" -D velocity=1e308 --quiet
refused "-D bad boolean" run "$source_dir/scenarios/mechanofusion_demo.lua" -D scraper=yes --quiet
refused "-D for a scene without parameters" run "$source_dir/tests/scenes/features_3d.lua" -D x=1 --quiet
refused "-Dname without =" run "$scene" -Dvelocity
refused "two scenes" run "$scene" "$scene"
refused "models with an argument" models extra
refused "api with an unknown name" api no_such_function
refused "api with two names" api fill run
refused "--version with an argument" --version extra

# ---- granule sweep: refused before any case runs ----
refused "sweep without a scene" sweep
refused "sweep of a missing scene" sweep no_such_scene.lua -D velocity=1,2
refused "sweep: empty list value" sweep "$scene" -D velocity=1,,2 -o sweep_out
refused "sweep: trailing comma" sweep "$scene" -D velocity=1, -o sweep_out
refused "sweep: a name twice" sweep "$scene" -D velocity=1 -D velocity=2 -o sweep_out
refused "sweep: a value twice" sweep "$scene" -D velocity=1,1 -o sweep_out
refused "sweep: unknown parameter" sweep "$scene" -D velocty=1,2 -o sweep_out
refused "sweep: not a number" sweep "$scene" -D velocity=1,fast -o sweep_out
refused "sweep: --restart" sweep "$scene" --restart x.h5
refused "sweep: -o empty" sweep "$scene" -o ""
refused "sweep: unknown option" sweep "$scene" --frobnicate
refused "sweep: --case-timeout 0" sweep "$scene" --case-timeout 0
refused "sweep: --case-timeout text" sweep "$scene" --case-timeout soon
refused "sweep: --case-timeout without a value" sweep "$scene" --case-timeout

# ---- malformed scenes ----
scene_file empty.lua ""
printf '\000\001\002garbage\377' >binary.lua
scene_file syntax.lua 'local sim = simulation { dimension = 2'
scene_file runtime.lua 'error("deliberate")'
scene_file nonstring_error.lua 'error({})'
scene_file global.lua 'x = 1'
scene_file undeclared.lua 'print(undeclared_name)'
scene_file dimension.lua 'simulation { dimension = 4 }'
scene_file dimension_nan.lua 'simulation { dimension = 0/0 }'
scene_file unknown_key.lua 'simulation { dimenson = 2 }'
scene_file wrong_type.lua 'simulation { dimension = "two" }'
scene_file params_twice.lua 'parameters { a = 1 } parameters { b = 2 }'
scene_file params_nan.lua 'parameters { a = 0/0 }'
scene_file params_table.lua 'parameters { a = {} }'
scene_file params_key.lua 'parameters { a = { defualt = 1 } }'
scene_file params_unit.lua 'parameters { a = { default = 1, unit = 5 } }'
scene_file params_positional.lua 'parameters { 1, 2 }'
scene_file params_arity.lua 'parameters({ a = 1 }, 2)'
scene_file params_readonly.lua 'local p = parameters { a = 1 } p.a = 2'
scene_file params_unknown.lua 'local p = parameters { a = 1 } print(p.b)'
scene_file no_law.lua 'local sim = simulation { dimension = 2 }
sim:material { name = "m", density = 1000 }
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "m" }
sim:add_particle { position = { 3e-3, 0 }, radius = 1e-3, material = "m" }
sim:run { steps = 1 }'
scene_file blowup.lua 'local sim = simulation { dimension = 2, time_step = 1e-3 }
sim:material { name = "m", density = 1000 }
sim:contact { "m", "m", model = "linear", k_normal = 1e6, restitution = 0.5 }
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "m" }
sim:add_particle { position = { 1e-3, 0 }, radius = 1e-3, material = "m" }
sim:run { steps = 10 }'
scene_file callback.lua 'local sim = simulation { dimension = 2 }
sim:material { name = "m", density = 1000 }
sim:contact { "m", "m", model = "linear", k_normal = 1e3, restitution = 0.5 }
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "m" }
sim:every { steps = 1, function(s) error("callback fails") end }
sim:run { steps = 10 }'
scene_file reentrant.lua 'local sim = simulation { dimension = 2 }
sim:material { name = "m", density = 1000 }
sim:contact { "m", "m", model = "linear", k_normal = 1e3, restitution = 0.5 }
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "m" }
sim:every { steps = 1, function(s) s:run { steps = 1 } end }
sim:run { steps = 10 }'
scene_file too_long.lua 'local sim = simulation { dimension = 2 }
sim:material { name = "m", density = 1000 }
sim:contact { "m", "m", model = "linear", k_normal = 1e3, restitution = 0.5 }
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "m" }
sim:run { duration = 1e300 }'
scene_file output_dir.lua 'local sim = simulation { dimension = 2 }
sim:output { file = "." }'
scene_file picture_bad.lua 'local sim = simulation { dimension = 2 }
sim:picture { file = "x.gif" }'
for f in empty binary syntax runtime nonstring_error global undeclared dimension dimension_nan \
         unknown_key wrong_type params_twice params_nan params_table params_key params_unit \
         params_positional params_arity params_readonly params_unknown no_law blowup callback \
         reentrant too_long output_dir picture_bad; do
  case $f in
    empty) ;;  # an empty scene is a valid (if idle) program: checked below to succeed
    *) refused "scene $f.lua" run "$f.lua" --quiet ;;
  esac
done
count=$((count + 1))
if ! "$granule" run empty.lua --quiet >/dev/null 2>&1; then
  echo "FAIL: an empty scene should run and do nothing"
  failures=$((failures + 1))
fi

# The REPL keeps going after errors but reports them in its exit status when scripted.
count=$((count + 1))
printf 'error("x")\nsimulation { dimension = 7 }\nreturn 1 + 1\n' | "$granule" repl >out.txt 2>err.txt
status=$?
if [ "$status" -ne 1 ] || ! grep -q '^2$' out.txt || [ "$(grep -c '^error:' out.txt)" -ne 2 ]; then
  echo "FAIL: piped REPL: status $status, output: $(cat out.txt)"
  failures=$((failures + 1))
fi

if [ "$failures" -ne 0 ]; then
  echo "$failures of $count malformed command lines were not refused properly"
  exit 1
fi
echo "fuzz_cli ok: $count command lines"
