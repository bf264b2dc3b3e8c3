#!/usr/bin/python3
"""Corrupt copies of a valid checkpoint, for the corpus (run_corpus.py).

    /usr/bin/python3 tests/corpus/make_checkpoints.py VALID.chk.h5 OUTDIR   # writes OUTDIR/<case>.h5

Each case changes one thing in a copy of a checkpoint that
checkpoint_scene.lua wrote at step 20 (40 discs with contacts): a truncated
or mis-sized array, NaN or inf, a negative mass, an index out of range, a
missing dataset, a time step above the stability limit, a wrong format
attribute, or a file that is not HDF5 at all. `expect` is the regular
expression the refusal must match: the field (dataset) it names, or the file.
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

G = "checkpoint/"
D, I, T = G + "doubles/", G + "integers/", G + "texts/"


def setter(path, fn):
    """A corruption that replaces dataset `path` with fn(old values)."""
    def apply(f):
        old = f[path][()]
        new = fn(np.array(old))
        del f[path]
        f[path] = new
    return apply


def set_at(path, index, value):
    def fn(a):
        a = a.copy()
        a[index] = value
        return a
    return setter(path, fn)


def delete(path):
    def apply(f):
        del f[path]
    return apply


def set_attr(name, value):
    def apply(f):
        if value is None:
            del f["checkpoint"].attrs[name]
        else:
            f["checkpoint"].attrs[name] = value
    return apply


def set_text(path, fn):
    def apply(f):
        old = f[path][()]
        old = old.decode() if isinstance(old, bytes) else str(old)
        del f[path]
        f[path] = fn(old)
    return apply


# name, what is wrong, corruption applied to an h5py file, expect regex
H5_CASES = [
    ("truncated_position", "particles.position one value short", setter(D + "particles.position", lambda a: a[:-1]), r"particles\.position"),
    ("truncated_radius", "particles.radius one value short", setter(D + "particles.radius", lambda a: a[:-1]), r"particles\.radius"),
    ("truncated_ids", "particles.id one value short (the other arrays are longer)", setter(I + "particles.id", lambda a: a[:-1]), r"particles\."),
    ("extra_velocity", "particles.velocity with an extra value", setter(D + "particles.velocity", lambda a: np.append(a, 0.0)), r"particles\.velocity"),
    ("position_2d_array", "particles.position stored as a 2D array of the wrong shape", setter(D + "particles.position", lambda a: a.reshape(2, -1)), r"particles\.position"),
    ("nan_position", "a NaN particle position", set_at(D + "particles.position", 3, np.nan), r"particles\.position"),
    ("inf_velocity", "an infinite particle velocity", set_at(D + "particles.velocity", 0, np.inf), r"particles\.velocity"),
    ("nan_spin", "a NaN spin", set_at(D + "particles.spin", 1, np.nan), r"particles\.spin"),
    ("negative_mass", "a negative particle mass", set_at(D + "particles.mass", 2, -1.0), r"particles\.(inv_)?mass"),
    ("negative_inv_mass", "a negative inverse mass", set_at(D + "particles.inv_mass", 2, -1.0), r"particles\.inv_mass"),
    ("zero_radius", "a particle of radius 0", set_at(D + "particles.radius", 0, 0.0), r"particles\.radius"),
    ("nan_inv_inertia", "a NaN inverse moment of inertia", set_at(D + "particles.inv_inertia", 4, np.nan), r"particles\.inv_inertia"),
    ("material_out_of_range", "a particle's material index beyond the materials", set_at(I + "particles.material", 0, 99), r"particles\.material|material"),
    ("material_negative", "a negative material index", set_at(I + "particles.material", 0, -1), r"particles\.material|material"),
    ("index_of_id_out_of_range", "index_of_id pointing past the particles", set_at(I + "particles.index_of_id", 0, 100000), r"particles\.index_of_id"),
    ("duplicate_id", "two particles with the same id", set_at(I + "particles.id", 1, 0), r"particles\.id"),
    ("fixed_flag_seven", "a fixed flag that is neither 0 nor 1", set_at(I + "particles.fixed", 0, 7), r"particles\.fixed"),
    ("pair_index_out_of_range", "a contact naming particle 10^6", set_at(I + "pairs.linear.i", 0, 1000000), r"pairs\.linear\.(i|j)"),
    ("pair_index_negative", "a contact naming particle -1", set_at(I + "pairs.linear.j", 0, -1), r"pairs\.linear\.(i|j)"),
    ("pair_arrays_differ", "a contact list whose i and j differ in length", setter(I + "pairs.linear.j", lambda a: a[:-1]), r"pairs\.linear"),
    ("pair_history_truncated", "contact histories cut short", setter(G + "bytes/pairs.linear.history", lambda a: a[:-3]), r"pairs\.linear\.history"),
    ("wall_contact_wall_out_of_range", "a wall contact naming wall 7 of 1", set_at(I + "walls.walton_braun.wall", 0, 7), r"walls\.walton_braun\.wall"),
    ("wall_contact_particle_out_of_range", "a wall contact naming particle 10^6", set_at(I + "walls.walton_braun.particle", 0, 1000000), r"walls\.walton_braun\.particle"),
    ("layout_wrong_size", "a history size that is not this build's", set_at(I + "pairs.linear.layout", 1, 3), r"pairs\.linear"),
    ("time_step_above_limit", "a time step (1 ms) far above the stability limit", lambda f: (set_at(D + "meta", 1, 1e-3)(f), set_at(D + "meta", 2, 1e-3)(f)), r"time_step|time step"),
    ("nan_time", "a NaN simulated time", set_at(D + "meta", 0, np.nan), r"time"),
    ("negative_step", "a negative step count", set_at(I + "meta", 2, -5), r"step"),
    ("nan_skin", "a NaN neighbour skin", set_at(D + "meta", 4, np.nan), r"skin"),
    ("zero_steps_per_contact", "steps_per_contact 0", set_at(D + "meta", 3, 0.0), r"steps_per_contact"),
    ("wrong_dimension", "a 3D checkpoint for a 2D scene", set_at(I + "meta", 1, 3), r"3D"),
    ("huge_next_id", "a next id of 10^15 (an allocation of petabytes if trusted)", set_at(I + "meta", 3, 10**15), r"particles\.|id"),
    ("nan_density", "a NaN material density", set_at(D + "materials", 0, np.nan), r"density|materials"),
    ("nan_wall_angular_velocity", "a NaN wall angular velocity", set_at(D + "walls", 6, np.nan), r"walls|angular_velocity"),
    ("nan_gravity", "a NaN gravity", set_at(D + "body", 2, np.nan), r"body|gravity"),
    ("nan_hook_time", "a NaN origin for a hook's period count", set_at(D + "hooks.origin_time", 1, np.nan), r"hooks"),
    ("contact_value_not_number", "a contact law value that is not a number", set_text(T + "contacts", lambda s: s.replace("k_normal=10000", "k_normal=stiff")), r"contacts.*(k_normal|stiff)"),
    ("contact_unknown_model", "a contact law of a model that does not exist", set_text(T + "contacts", lambda s: s.replace("\tlinear\t", "\thooke\t")), r"hooke"),
    ("missing_velocity", "particles.velocity missing", delete(D + "particles.velocity"), r"particles\.velocity"),
    ("missing_materials_text", "the material names missing", delete(T + "materials"), r"materials"),
    ("missing_integers_group", "the whole integers group missing", delete(G + "integers"), r"integers|meta"),
    ("position_as_text", "particles.position stored as strings", setter(D + "particles.position", lambda a: np.array([b"x"] * len(a))), r"particles\.position"),
    ("mass_as_integers", "particles.mass stored as integers", setter(D + "particles.mass", lambda a: np.ones(len(a), dtype=np.int64)), r"particles\.mass"),
    ("wrong_format", "a format attribute of another program", set_attr("format", "liggghts-restart-3"), r"format"),
    ("no_format", "no format attribute", set_attr("format", None), r"format"),
    ("no_checkpoint_group", "an HDF5 file without the checkpoint group", lambda f: f.move("checkpoint", "elsewhere"), r"checkpoint"),
]


def not_hdf5(path, valid):
    with open(path, "w") as f:
        f.write("this is not a checkpoint\n" * 10)


def empty(path, valid):
    open(path, "w").close()


def truncated_file(path, valid):
    with open(valid, "rb") as f:
        data = f.read()
    with open(path, "wb") as f:
        f.write(data[: len(data) // 2])


def garbage_tail(path, valid):
    with open(valid, "rb") as f:
        data = bytearray(f.read())
    for k in range(len(data) // 3, len(data), 7):
        data[k] ^= 0x5A
    with open(path, "wb") as f:
        f.write(bytes(data))


# name, what is wrong, writer(path, valid), expect (the file's name)
FILE_CASES = [
    ("not_hdf5", "a text file given as a checkpoint", not_hdf5, r"not_hdf5\.h5"),
    ("empty_file", "an empty file", empty, r"empty_file\.h5"),
    ("truncated_file", "the file cut in half", truncated_file, r"truncated_file\.h5"),
    ("scrambled_bytes", "every 7th byte of the file's last two thirds flipped", garbage_tail, r"scrambled_bytes\.h5|particles\.|checkpoint"),
]


def write_all(valid, outdir):
    """Writes every case to outdir/<name>.h5; returns [(name, what, expect)]."""
    os.makedirs(outdir, exist_ok=True)
    made = []
    for name, what, corrupt, expect in H5_CASES:
        path = os.path.join(outdir, name + ".h5")
        shutil.copyfile(valid, path)
        with h5py.File(path, "r+") as f:
            corrupt(f)
        made.append((name, what, expect))
    for name, what, writer, expect in FILE_CASES:
        writer(os.path.join(outdir, name + ".h5"), valid)
        made.append((name, what, expect))
    return made


def run_setup(command, cwd, failures, what):
    try:
        return subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        failures.append(f"{what}: no result within 60 s")
        return None


def cases(granule, here, work, failures):
    """Runs checkpoint_scene.lua for a valid checkpoint, then returns one corpus
    case per corruption (each in its own directory with its BAD.h5) and a
    control: the untouched checkpoint must restart (checked here)."""
    scene = os.path.join(here, "checkpoint_scene.lua")
    base = os.path.join(work, "checkpoint_valid")
    os.makedirs(base)
    r = run_setup([granule, "run", scene, "-o", "out.h5", "--quiet"], base, failures, "checkpoint_scene.lua")
    valid = os.path.join(base, "valid.chk.h5")
    if r is None:
        return []
    if r.returncode != 0 or not os.path.exists(valid):
        failures.append(f"checkpoint_scene.lua did not write a checkpoint (status {r.returncode}): {r.stderr[-500:]}")
        return []
    control = os.path.join(work, "checkpoint_control")
    os.makedirs(control)
    shutil.copyfile(valid, os.path.join(control, "copy.chk.h5"))
    r = run_setup([granule, "run", scene, "--restart", "copy.chk.h5", "-o", "out.h5", "--quiet"], control,
                  failures, "restart from the untouched checkpoint")
    if r is not None and r.returncode != 0:
        failures.append(f"the untouched checkpoint does not restart (status {r.returncode}): {r.stderr[-500:]}")
    out = []
    for name, what, expect in write_all(valid, os.path.join(work, "checkpoint_files")):
        case_name = "checkpoint_" + name
        wd = os.path.join(work, case_name)
        os.makedirs(wd)
        shutil.move(os.path.join(work, "checkpoint_files", name + ".h5"), os.path.join(wd, name + ".h5"))
        out.append(dict(name=case_name, kind="checkpoint", what=what, expect=expect,
                        command=["run", scene, "--restart", os.path.join(wd, name + ".h5")]))
    return out


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    for name, what, _ in write_all(sys.argv[1], sys.argv[2]):
        print(f"{name}: {what}")
