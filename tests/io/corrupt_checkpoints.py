"""Damaged checkpoint files, end to end: `granule run SCENE --restart bad.h5` must end
with a message naming the damaged entry and exit status 1 or 2, never a signal, never a
run. Usage: corrupt_checkpoints.py GRANULE SOURCE_DIR WORK_DIR
Makes one good checkpoint of tests/scenes/restart.lua, then copies of it with one entry
damaged each (an index table out of range, a negative inverse mass, a time step above
the stability limit, a short array, NaN, an entry left out, an array of another shape or
type, a bit flipped on disk) and two files that are not checkpoints (truncated, garbage); prints
"corrupt_checkpoints ok" when every one was refused as it must be.
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

granule, source, work = sys.argv[1:4]
scene = os.path.join(source, "tests", "scenes", "restart.lua")
work = os.path.join(work, "corrupt_checkpoints")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
good = os.path.join(work, "good.chk.h5")
# The restarts give the same -D values: a restart must replay the run that wrote the file.
parameters = ["-D", "checkpoint=" + good, "-D", "stage2_steps=1000"]
subprocess.run([granule, "run", scene, *parameters, "-o", os.path.join(work, "good.h5"),
                "--quiet"], check=True, stdout=subprocess.DEVNULL)


def damaged(name, change):
    path = os.path.join(work, name + ".chk.h5")
    shutil.copy(good, path)
    with h5py.File(path, "r+") as f:
        change(f["checkpoint"])
    return path


def set_value(group, key, index, value):
    def change(c):
        data = c[group][key][:]
        data[index] = value
        c[group][key][...] = data
    return change


def replace(group, key, make):
    def change(c):
        data = c[group][key][:]
        del c[group][key]
        c[group].create_dataset(key, data=make(data))
    return change


def remove(group, key):
    def change(c):
        del c[group][key]
    return change


cases = [  # (file, the text the message must hold)
    (damaged("pair_index", set_value("integers", "pairs.walton_braun.i", 0, 10**6)),
     "'pairs.walton_braun.i'"),
    (damaged("wall_index", set_value("integers", "walls.walton_braun.wall", 0, 7)),
     "'walls.walton_braun.wall'"),
    (damaged("id_table", set_value("integers", "particles.index_of_id", 5, -7)),
     "'particles.index_of_id'"),
    (damaged("negative_inv_mass", set_value("doubles", "particles.inv_mass", 3, -1.0)),
     "'particles.inv_mass'"),
    (damaged("time_step", set_value("doubles", "meta", 1, 1e-3)), "stability limit"),
    (damaged("nan_radius", set_value("doubles", "particles.radius", 0, np.nan)),
     "'particles.radius'"),
    (damaged("inf_position", set_value("doubles", "particles.position", 0, np.inf)),
     "'particles.position'"),
    (damaged("short_velocity", replace("doubles", "particles.velocity", lambda d: d[:-1])),
     "'particles.velocity'"),
    (damaged("missing_ids", remove("integers", "particles.id")), "'particles.id'"),
    (damaged("two_d_spin", replace("doubles", "particles.spin", lambda d: d.reshape(-1, 1))),
     "particles.spin"),
    (damaged("text_mass", replace("doubles", "particles.mass",
                                  lambda d: np.array([b"heavy"] * len(d)))), "particles.mass"),
    (damaged("history_bytes", replace("bytes", "pairs.walton_braun.history", lambda d: d[:-3])),
     "'pairs.walton_braun.history'"),
]
# One bit of a position flipped on disk, past HDF5 (a bad sector): the value is still a
# plausible number, so only the array's checksum tells.
flipped = os.path.join(work, "flipped_bit.chk.h5")
shutil.copy(good, flipped)
with h5py.File(flipped, "r") as f:
    dataset = f["checkpoint/doubles/particles.position"]
    offset = dataset.id.get_chunk_info(0).byte_offset
with open(flipped, "r+b") as f:
    f.seek(offset + 8 * 3 + 2)  # the fourth double's third byte: its mantissa
    byte = f.read(1)[0]
    f.seek(offset + 8 * 3 + 2)
    f.write(bytes([byte ^ 0x10]))
cases.append((flipped, "particles.position"))
truncated = os.path.join(work, "truncated.chk.h5")
with open(good, "rb") as f:
    data = f.read()
with open(truncated, "wb") as f:
    f.write(data[: len(data) // 2])
cases.append((truncated, "truncated.chk.h5"))
garbage = os.path.join(work, "garbage.chk.h5")
with open(garbage, "wb") as f:
    f.write(b"\x89HDF\r\n\x1a\n" + bytes(range(256)) * 64)
cases.append((garbage, "garbage.chk.h5"))

failures = []
for path, needle in cases:
    p = subprocess.run([granule, "run", scene, *parameters, "--restart", path, "-o",
                        os.path.join(work, "out.h5"), "--quiet"],
                       capture_output=True, text=True, timeout=120)
    text = p.stdout + p.stderr
    name = os.path.basename(path)
    if p.returncode not in (1, 2):
        failures.append(f"{name}: exit status {p.returncode} (must be 1 or 2)\n{text}")
    elif needle not in text or "checkpoint" not in text:
        failures.append(f"{name}: the message does not name {needle}:\n{text}")
    else:
        print(f"{name}: refused ({text.strip().splitlines()[0][:160]})")
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("corrupt_checkpoints ok")
