#!/usr/bin/env python3
"""The bad-input corpus of the stage scripts and the tools (tests/bad_input/scripts.cases), run by
ctest as integration.bad_input_scripts.

Every case is one mistake a user can make with a stage script of examples/manufacturing (a -var,
the settings of an older ncf-gen, the restart file of another stage or fabric) or with a tool
(ncf-gen's card and options, ncf-measure, ncf-overlaps, ncf-export, ncf-perm), and names the text
its message must hold (the script or tool, the variable, key or option, the value). A case passes
when the command exits with a non-zero status, its output holds that text, it prints no Python
traceback and it leaves no new file in its folder (the inputs are checked before anything is
written). Lines starting with 'ok' are control cases: the command must succeed, so that a check
that refuses everything fails them.

Corpus format, one case per line ('#' lines and blank lines are comments):

    NAME | COMMAND | EXPECTED TEXT
    ok NAME | COMMAND |

COMMAND is one of
    lmp SCRIPT ARGS...     lmp -in examples/manufacturing/in.SCRIPT ARGS (nothing added)
    stage SCRIPT ARGS...   lmp -in examples/manufacturing/in.SCRIPT -var prefix small -var here ...
    vt SCRIPT ARGS...      lmp -in examples/virtual-tests/in.SCRIPT -var prefix small -var here ...
                           ARGS (ARGS come first: LAMMPS keeps the first -var, so -var prefix P
                           in ARGS picks one of the prepared fabrics below)
    gen EDIT; EDIT...      ncf-gen on examples/manufacturing/small.card with edits:
                           set KEY VALUE... (the first line of KEY becomes KEY VALUE...; appended
                           when there is none), add LINE, drop KEY, bom (a UTF-8 byte-order mark
                           first), args ARGS... (ncf-gen's options after the card)
    tool NAME ARGS...      the tool NAME of the build folder with ARGS
    run [VAR=VALUE...] ARGS...  examples/manufacturing/run.sh ARGS with those environment variables
Words are split as the shell does (shlex). The prepared fabrics, in every case's folder: small
(the small card generated, with restart files of every stage written by stage_restart.lmp), old
(its settings without the variables of this ncf-gen), other (seed 8: another fabric), mix (small's
settings with other's restart files), wrong (each stage's restart file is the one of the stage
before it; the compaction's is the piercing's), longer (a card with longer stitches: another RVE
size), farneedles (small with the needle file of another fabric), nomark (restart files without a stage mark), norestart (no restart files), and a few
files for the tools (see prepare()).

NCF_BAD_INPUT_SHOW=1 prints every case's message; NCF_BAD_INPUT_ONLY=NAME runs the cases whose
name contains NAME.
"""
import os
import shlex
import shutil
import subprocess
import sys
import tempfile

ROOT = os.environ.get("NCF_ROOT") or os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD = os.environ.get("NCF_BUILD") or os.path.join(ROOT, "build")
HERE = os.path.join(ROOT, "examples", "manufacturing")
CORPUS = os.path.join(ROOT, "tests", "bad_input", "scripts.cases")
STAGES = ["compact", "pierce", "stitch", "pretension", "release"]


def env():
    e = dict(os.environ)
    with open(os.path.join(BUILD, "ncf-env.sh")) as f:
        for line in f:
            line = line.strip()
            if line.startswith("export ") and "=" in line and " " not in line[7:].split("=", 1)[0]:
                k, v = line[7:].split("=", 1)
                if v.startswith('"') and v.endswith('"'):
                    v = v[1:-1]
                v = v.replace("$PATH", e.get("PATH", "")).replace(
                    "${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}",
                    ":" + e["LD_LIBRARY_PATH"] if e.get("LD_LIBRARY_PATH") else "")
                e[k] = v
    e["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
    e["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    return e


ENV = None


def run(cmd, cwd, timeout=120):
    p = subprocess.run(cmd, cwd=cwd, env=ENV, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, errors="replace", timeout=timeout)
    return p.returncode, p.stdout


def must(cmd, cwd):
    rc, out = run(cmd, cwd)
    if rc != 0:
        sys.exit("run_cases: preparing the corpus failed: %s\n%s" % (" ".join(cmd), out))
    return out


def card_text(path=os.path.join(HERE, "small.card")):
    text = open(path).read()
    return text.replace("../../potentials/ncf.materials", os.path.join(ROOT, "potentials", "ncf.materials"))


RESTART_SCRIPT = """# a restart file of a stage, with the stage's mark, without running the stages before
units           si
atom_style      angle
atom_modify     map array
boundary        p p f
newton          on
bond_style      ncf/chain
fix             NCF_NODE all property/atom i_ncf_layer i_ncf_end ghost yes
read_data       ${prefix}.layers.data fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0 fix NCF_NODE NULL NCF_NODE
include         ${prefix}.settings.lmp
if "${mark} == 1" then "ncf/check prepare mark ${stage} ${ncf_fabric}"
write_restart   ${out}.${stage}.restart
"""


def prepare(base):
    """The fabrics and files every case's folder links to."""
    with open(os.path.join(base, "small.card"), "w") as f:
        f.write(card_text())
    must(["ncf-gen", "small.card", "-o", "small", "-q"], base)
    must(["ncf-gen", "small.card", "-o", "other", "-q", "-seed", "8"], base)
    with open(os.path.join(base, "stage_restart.lmp"), "w") as f:
        f.write(RESTART_SCRIPT)
    lmp = ["lmp", "-log", "none", "-screen", "none", "-in", "stage_restart.lmp"]
    for stage in STAGES[:4]:
        for fab, out, mark in (("small", "small", 1), ("other", "other", 1), ("small", "nomark", 0)):
            must(lmp + ["-var", "prefix", fab, "-var", "out", out, "-var", "stage", stage,
                        "-var", "mark", str(mark)], base)
    gen = [".layers.data", ".yarn.data", ".needles", ".settings.lmp", ".yarn.lmp", ".summary"]
    for fab in ("old", "mix", "wrong", "nomark", "norestart", "farneedles"):
        for ext in gen:
            shutil.copy(os.path.join(base, "small" + ext), os.path.join(base, fab + ext))
    for k, stage in enumerate(STAGES[:4]):
        for fab in ("old", "farneedles"):
            shutil.copy(os.path.join(base, "small.%s.restart" % stage),
                        os.path.join(base, "%s.%s.restart" % (fab, stage)))
        shutil.copy(os.path.join(base, "other.%s.restart" % stage),
                    os.path.join(base, "mix.%s.restart" % stage))
        if k > 0:
            shutil.copy(os.path.join(base, "small.%s.restart" % STAGES[k - 1]),
                        os.path.join(base, "wrong.%s.restart" % stage))
    shutil.copy(os.path.join(base, "small.pierce.restart"), os.path.join(base, "wrong.compact.restart"))
    # a fabric of another RVE size (longer stitches): its summary does not fit small's data
    with open(os.path.join(base, "longer.card"), "w") as f:
        f.write(card_text().replace("stitch_length   1.2 mm", "stitch_length   1.4 mm"))
    must(["ncf-gen", "longer.card", "-o", "longer", "-q"], base)
    # the needle file of another fabric: a stitching point outside this fabric's box
    with open(os.path.join(base, "farneedles.needles"), "w") as f:
        f.write("6e-04 0.00127\n0.5 0.00127\n")
    # the settings of an older ncf-gen: without the fabric's identity, the needle pitch and the
    # quality preset's run parameters
    drop = ("variable ncf_fabric", "variable ncf_needle_pitch", "variable ncf_dtfrac",
            "variable ncf_pdyn", "variable ncf_tau", "variable ncf_quality")
    text = open(os.path.join(base, "small.settings.lmp")).read().splitlines(True)
    with open(os.path.join(base, "old.settings.lmp"), "w") as f:
        f.writelines(l for l in text if not l.startswith(drop))
    # files for the tools
    files = {
        "twice.needles": "# the same point twice\n6e-04 0.00127\n6e-04 0.00127\n",
        "one.needles": "6e-04 0.00127\n",
        "far.needles": "6e-04 0.00127\n0.5 0.00127\n",
        "bad.needles": "6e-04 abc\n0.0018 0.00127\n",
        "nan.needles": "6e-04 nan\n0.0018 0.00127\n",
        "empty.data": "",
        "garbage.data": "this is not a data file\n",
        "notgrid.vti": "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"></VTKFile>\n",
    }
    for name, text in files.items():
        with open(os.path.join(base, name), "w") as f:
            f.write(text)
    os.mkdir(os.path.join(base, "afolder"))
    with open(os.path.join(base, "afile"), "w") as f:
        f.write("an existing file\n")


def read_corpus():
    cases = []
    with open(CORPUS) as f:
        for n, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            parts = [p.strip() for p in s.split("|")]
            if len(parts) != 3:
                sys.exit("%s:%d: expected 'NAME | COMMAND | EXPECTED', got: %s" % (CORPUS, n, s))
            name, cmd, expect = parts
            ok = name.startswith("ok ")
            if ok:
                name = name[3:].strip()
            elif not expect:
                sys.exit("%s:%d: case %s expects no text (every case names its message)" % (CORPUS, n, name))
            cases.append(dict(name=name, cmd=cmd, expect=expect, ok=ok, line=n))
    names = [c["name"] for c in cases]
    dup = sorted(set(x for x in names if names.count(x) > 1))
    if dup:
        sys.exit("%s: case names given twice: %s" % (CORPUS, ", ".join(dup)))
    return cases


def gen_command(spec, folder):
    lines = card_text().splitlines()
    args = []
    bom = False
    for edit in [e.strip() for e in spec.split(";") if e.strip()]:
        w = edit.split(None, 1)
        op, rest = w[0], (w[1] if len(w) > 1 else "")
        if op == "set":
            key = rest.split()[0]
            for i, l in enumerate(lines):
                if l.split() and l.split()[0] == key:
                    lines[i] = rest
                    break
            else:
                lines.append(rest)
        elif op == "add":
            lines.append(rest)
        elif op == "drop":
            lines = [l for l in lines if not (l.split() and l.split()[0] == rest)]
        elif op == "bom":
            bom = True
        elif op == "args":
            args += shlex.split(rest)
        else:
            raise ValueError("unknown card edit '%s'" % edit)
    text = "\n".join(lines) + "\n"
    with open(os.path.join(folder, "case.card"), "wb") as f:
        f.write((b"\xef\xbb\xbf" if bom else b"") + text.encode())
    return ["ncf-gen", "case.card", "-o", "case"] + args


def command(case, folder):
    w = case["cmd"].replace("@HERE@", HERE).split(None, 1)
    kind, rest = w[0], (w[1] if len(w) > 1 else "")
    if kind == "stage":
        a = shlex.split(rest)
        return ["lmp", "-log", "none", "-echo", "none", "-in", os.path.join(HERE, "in." + a[0])] + \
            a[1:] + ["-var", "prefix", "small", "-var", "here", HERE]
    if kind == "vt":    # the virtual tests (examples/virtual-tests), on the prepared fabric small
        a = shlex.split(rest)
        vt = os.path.join(ROOT, "examples", "virtual-tests")
        return ["lmp", "-log", "none", "-echo", "none", "-in", os.path.join(vt, "in." + a[0])] + \
            a[1:] + ["-var", "prefix", "small", "-var", "here", vt]
    if kind == "lmp":
        a = shlex.split(rest)
        return ["lmp", "-log", "none", "-echo", "none", "-in", os.path.join(HERE, "in." + a[0])] + a[1:]
    if kind == "run":
        a = shlex.split(rest)
        return ["env"] + a[:next((i for i, w in enumerate(a) if "=" not in w), len(a))] + \
            ["bash", os.path.join(HERE, "run.sh")] + [w for w in a if "=" not in w]
    if kind == "gen":
        return gen_command(rest, folder)
    if kind == "tool":
        a = shlex.split(rest)
        return [os.path.join(BUILD, a[0])] + a[1:]
    raise ValueError("unknown command kind '%s'" % kind)


def main():
    global ENV
    ENV = env()
    cases = read_corpus()
    only = os.environ.get("NCF_BAD_INPUT_ONLY")
    show = os.environ.get("NCF_BAD_INPUT_SHOW")
    out_root = os.path.join(BUILD, "test-output", "bad_input_scripts")
    shutil.rmtree(out_root, ignore_errors=True)
    os.makedirs(out_root)
    base = os.path.join(out_root, "base")
    os.makedirs(base)
    prepare(base)
    base_files = sorted(os.listdir(base))
    failed = []
    ran = 0
    for case in cases:
        if only and only not in case["name"]:
            continue
        ran += 1
        folder = tempfile.mkdtemp(prefix=case["name"][:40] + ".", dir=out_root)
        for name in base_files:
            os.symlink(os.path.join(base, name), os.path.join(folder, name))
        try:
            cmd = command(case, folder)
        except ValueError as e:
            failed.append((case, "bad case: %s" % e))
            continue
        before = set(os.listdir(folder))
        try:
            rc, out = run(cmd, folder)
        except subprocess.TimeoutExpired:
            failed.append((case, "timed out"))
            continue
        new = sorted(set(os.listdir(folder)) - before - {"case.card"})
        why = []
        if case["ok"]:
            if rc != 0:
                why.append("exit status %d, expected success" % rc)
        else:
            if rc == 0:
                why.append("exit status 0, expected an error")
            if case["expect"] not in out:
                why.append("message without '%s'" % case["expect"])
            if new:
                why.append("left files behind: %s" % ", ".join(new))
        if "Traceback (most recent call last)" in out:
            why.append("printed a Python traceback")
        msg = [l for l in out.splitlines() if "ERROR" in l or "error" in l]
        if show:
            print("%-45s %s" % (case["name"], msg[0] if msg else out.strip().splitlines()[-1:]))
        if why:
            failed.append((case, "; ".join(why) + "\n    command: %s\n    output:\n%s" % (
                " ".join(shlex.quote(c) for c in cmd),
                "\n".join("      " + l for l in out.strip().splitlines()[-12:]))))
        else:
            shutil.rmtree(folder, ignore_errors=True)
    for case, why in failed:
        print("FAIL %s (scripts.cases:%d): %s" % (case["name"], case["line"], why))
    nok = sum(1 for c in cases if c["ok"] and (not only or only in c["name"]))
    print("bad-input corpus of the stage scripts and tools: %d of %d cases passed (%d error cases, "
          "%d controls)" % (ran - len(failed), ran, ran - nok, nok))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
