"""Output folders: only a command's own output is replaced, in one step, under a lock."""

from __future__ import annotations

import csv
import doctest
import errno
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from clearance.networks.samples import build as samples
from clearance.reports.cli.main import main
from clearance.reports.output import output_dir
from clearance.reports.output.output_dir import Layout, foreign_entries, marker_name, output_folder
from clearance.reports.results import simulate_files
from clearance.vehicles.errors import InputError
from clearance.vehicles.table import bundled_table

DEMO = Layout("demo", files=frozenset({"a.txt", "b.txt"}), folders={"sub": (".csv",)},
              signature=("a.txt", "demo,"))
ROOT = Path(__file__).resolve().parents[2]

NET = samples.SAMPLES_DIR / "intersection" / "intersection.net.xml"
CURVES = ("turn:X:XN_in_0->XW_out_0", "turn:T:TW_in_0->TS_out_0")
SIMULATE = ["simulate", "-n", str(NET), "-t", str(bundled_table("aashto_green_book")),
            "--vehicle", "P", "--no-sumo"]


def write_demo(path: Path, text: str = "demo,1\n") -> None:
    with output_folder(path, DEMO) as staging:
        (staging / "a.txt").write_text(text)
        (staging / "sub").mkdir()
        (staging / "sub" / "x.csv").write_text("1\n")


def tree(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` with its bytes."""
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


# -------------------------------------------------------------------- what is replaced


def test_a_new_folder_gets_the_marker_and_nothing_is_left_beside_it(tmp_path):
    write_demo(tmp_path / "out")
    assert tree(tmp_path / "out") == {".clearance-demo": (tmp_path / "out" /
                                                          ".clearance-demo").read_bytes(),
                                      "a.txt": b"demo,1\n", "sub/x.csv": b"1\n"}
    assert (tmp_path / "out" / marker_name("demo")).read_text().startswith(
        "clearance demo output, layout 1\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]  # no lock, no staging


def test_its_own_output_is_replaced_as_a_whole(tmp_path):
    out = tmp_path / "out"
    write_demo(out)
    with output_folder(out, DEMO) as staging:
        (staging / "b.txt").write_text("second")
    assert sorted(tree(out)) == [".clearance-demo", "b.txt"]  # nothing of the first left
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_folder_of_other_files_is_refused_and_untouched(tmp_path):
    mine = tmp_path / "mine"
    (mine / "sub").mkdir(parents=True)
    (mine / "thesis.txt").write_text("years of work")
    (mine / "a.txt").write_text("demo,but mine")
    (mine / "sub" / "notes.doc").write_text("x")
    before = tree(mine)
    with pytest.raises(InputError) as exc:
        write_demo(mine)
    message = str(exc.value)
    assert message.startswith(f"{mine}: the folder exists and is not a clearance demo output")
    assert "sub/notes.doc" in message and "thesis.txt" in message
    assert "a.txt" not in message  # a file the command writes is not in the way
    assert tree(mine) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine"]


@pytest.mark.parametrize("make, why", [
    (lambda p: p.write_text("x"), "exists and is not a folder"),
    (lambda p: (p.parent.joinpath("theirs").mkdir(), p.parent.joinpath("theirs", "x").touch(),
                os.symlink(p.parent / "theirs", p)), "it holds x"),
    (lambda p: (p.mkdir(), (p / ".clearance-report").write_text(
        "clearance report output, layout 1\n")), "holds clearance report's output"),
    (lambda p: (p.mkdir(), (p / ".clearance-demo").write_text("forged\n")),
     "holds another clearance command's output"),
    (lambda p: (p.mkdir(), (p / "sub").mkdir(), (p / "sub" / "x.csv").write_text("")),
     "it holds sub"),  # only a sub-folder: not recognisably an output from before markers
    (lambda p: (p.mkdir(), (p / "a.txt").write_text("someone's\n")), "it holds a.txt"),
    (lambda p: (p.mkdir(), os.symlink("/etc/passwd", p / "a.txt")), "it holds a.txt"),
])
def test_what_is_not_this_commands_output_is_refused(tmp_path, make, why):
    out = tmp_path / "out"
    make(out)
    before = sorted(os.listdir(tmp_path))
    with pytest.raises(InputError, match=why):
        write_demo(out)
    assert sorted(os.listdir(tmp_path)) == before


def test_a_link_to_an_output_folder_replaces_the_folder_and_keeps_the_link(tmp_path):
    real = tmp_path / "real"
    write_demo(real)
    os.symlink("real", tmp_path / "link")
    with output_folder(tmp_path / "link", DEMO) as staging:
        (staging / "b.txt").write_text("via the link")
    assert os.readlink(tmp_path / "link") == "real"
    assert sorted(tree(real)) == [".clearance-demo", "b.txt"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "real"]


def test_an_empty_folder_and_one_from_before_markers_are_replaced(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    write_demo(empty, "demo,2\n")
    assert (empty / "a.txt").read_text() == "demo,2\n"
    old = tmp_path / "old"  # the command's files, no marker: written before markers
    (old / "sub").mkdir(parents=True)
    (old / "a.txt").write_text("demo,0\n")
    (old / "sub" / "y.csv").write_text("")
    (old / ".b.txt.abc123.tmp").write_text("")  # an atomic write a kill interrupted
    write_demo(old)
    assert sorted(tree(old)) == [".clearance-demo", "a.txt", "sub/x.csv"]


def test_foreign_entries_docstring_examples():
    assert doctest.testmod(output_dir).failed == 0


def test_foreign_entries_names_nested_and_linked_entries(tmp_path):
    (tmp_path / "sub" / "deeper").mkdir(parents=True)
    (tmp_path / "sub" / "ok.csv").write_text("")
    os.symlink(tmp_path / "sub" / "ok.csv", tmp_path / "sub" / "link.csv")
    (tmp_path / "other").mkdir()
    assert foreign_entries(tmp_path, DEMO) == ["other", "sub/deeper", "sub/link.csv"]


# ------------------------------------------------------------------ failure and atomicity


@pytest.mark.parametrize("error", [RuntimeError("bug"), KeyboardInterrupt()])
def test_a_failing_or_interrupted_block_leaves_the_previous_output(tmp_path, error):
    out = tmp_path / "out"
    write_demo(out)
    before = tree(out)
    with pytest.raises(type(error)):
        with output_folder(out, DEMO) as staging:
            (staging / "a.txt").write_text("demo,new\n")
            raise error
    assert tree(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_the_swap_is_one_exchange_of_the_two_folders(tmp_path, monkeypatch):
    out = tmp_path / "out"
    write_demo(out)
    calls = []
    real = output_dir._exchange

    def exchange(a, b):
        calls.append((Path(a).stat().st_ino, Path(b).stat().st_ino))
        return real(a, b)

    monkeypatch.setattr(output_dir, "_exchange", exchange)
    with output_folder(out, DEMO) as staging:
        (staging / "b.txt").write_text("x")
        new_inode = staging.stat().st_ino
    if not calls:
        pytest.skip("renameat2(RENAME_EXCHANGE) is not available here")
    assert calls == [(new_inode, calls[0][1])]
    assert out.stat().st_ino == new_inode  # DIR is the staged folder itself, not a copy


def test_without_the_exchange_two_renames_and_a_failed_second_one_is_undone(
        tmp_path, monkeypatch):
    out = tmp_path / "out"
    write_demo(out)
    monkeypatch.setattr(output_dir, "_exchange", lambda a, b: False)
    with output_folder(out, DEMO) as staging:
        (staging / "b.txt").write_text("fallback")
    assert (out / "b.txt").read_text() == "fallback" and not (out / "a.txt").exists()
    before = tree(out)
    real_rename, seen = os.rename, []

    def rename(src, dst):
        seen.append(Path(dst).name)
        if len(seen) == 2:  # the staging folder to DIR
            raise KeyboardInterrupt
        real_rename(src, dst)

    monkeypatch.setattr(output_dir.os, "rename", rename)
    with pytest.raises(KeyboardInterrupt):
        with output_folder(out, DEMO) as staging:
            (staging / "a.txt").write_text("demo,3\n")
    monkeypatch.setattr(output_dir.os, "rename", real_rename)
    assert seen[0].startswith(".out.old-") and seen[1] == "out" and seen[2] == "out"
    assert tree(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_kill_between_the_two_renames_is_repaired_by_the_next_run(tmp_path):
    out = tmp_path / "out"
    write_demo(out, "demo,old\n")
    before = tree(out)
    os.rename(out, tmp_path / ".out.old-4242-deadbeef")  # what the kill left: no DIR
    with pytest.raises(RuntimeError):  # the next run fails: the old output is back
        with output_folder(out, DEMO):
            raise RuntimeError
    assert tree(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_leftovers_of_killed_runs_are_removed_when_they_are_ours(tmp_path):
    out = tmp_path / "out"
    write_demo(out)
    ours = tmp_path / ".out.new-123-abcdefgh"  # a killed run's staging folder
    (ours / "sub").mkdir(parents=True)
    (ours / ".clearance-demo").write_text("clearance demo output, layout 1\n")
    (ours / "sub" / "x.csv").write_text("1\n")
    today = tmp_path / ".out.new-k2j3h4g5"  # from before markers: the command's files
    today.mkdir()
    (today / "a.txt").write_text("demo,1\n")
    empty = tmp_path / ".out.old-77-00000000"
    empty.mkdir()
    foreign = tmp_path / ".out.new-999-zzzzzzzz"  # a name like ours, someone else's files
    foreign.mkdir()
    (foreign / "thesis.txt").write_text("x")
    other = tmp_path / ".outer.new-1-abc"  # another output folder's
    other.mkdir()
    write_demo(out)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["out", foreign.name, other.name])
    assert (foreign / "thesis.txt").read_text() == "x"


LOCK_HOLDER = """
import sys, time
sys.path.insert(0, sys.argv[2])
from test_output_dir import DEMO
from clearance.reports.output.output_dir import output_folder
with output_folder(sys.argv[1], DEMO) as staging:
    (staging / "a.txt").write_text("demo,half\\n")
    print(staging, flush=True)
    time.sleep(120)
"""


def test_a_second_run_refuses_and_a_killed_holder_leaves_nothing_behind(tmp_path):
    out = tmp_path / "out"
    write_demo(out, "demo,previous\n")
    before = tree(out)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    holder = subprocess.Popen([sys.executable, "-c", LOCK_HOLDER, str(out),
                               str(Path(__file__).parent)], stdout=subprocess.PIPE,
                              text=True, env=env)
    try:
        staging = Path(holder.stdout.readline().strip())
        assert staging.parent == tmp_path and staging.name.startswith(f".out.new-{holder.pid}-")
        with pytest.raises(InputError) as exc:
            write_demo(out, "demo,second\n")
        assert str(exc.value) == (f"{out}: another clearance run (process {holder.pid}) is "
                                  "writing this folder; wait for it to finish or give "
                                  "another -o folder")
        assert tree(out) == before and staging.is_dir()  # neither touched the other
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait(timeout=30)
    assert tree(out) == before  # killed while writing: the previous output is whole
    write_demo(out, "demo,third\n")  # the lock died with the process; its folder is removed
    assert (out / "a.txt").read_text() == "demo,third\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_the_lock_file_is_only_removed_by_its_holder(tmp_path):
    out = tmp_path / "out"
    with output_folder(out, DEMO):
        lock = tmp_path / ".out.lock"
        assert lock.read_text() == f"{os.getpid()}\n"
        with pytest.raises(InputError, match=f"process {os.getpid()}"):
            write_demo(out)
        assert lock.is_file()  # the refused run did not remove the holder's lock
    assert not lock.exists()


# ----------------------------------------------------------------- paths that cannot be


@pytest.mark.parametrize("given, why", [
    (".", "it is the current folder or holds it"),
    ("..", "it is the current folder or holds it"),
    ("/", "it is the root"),
    ("/proc/x", "cannot write in the folder /proc: No such file or directory"),
    ("a_file/out", "cannot create the folder"),
])
def test_impossible_output_paths_exit_2(tmp_path, monkeypatch, capsys, given, why):
    monkeypatch.chdir(tmp_path)
    Path("a_file").write_text("x")
    assert main([*SIMULATE, "--curve", CURVES[0], "-o", given]) == 2
    err = capsys.readouterr().err
    assert f"error: {given}: " in err and why in err and "Traceback" not in err
    assert sorted(os.listdir(tmp_path)) == ["a_file"]


# -------------------------------------------------------------------- simulate as a whole


@pytest.fixture
def previous(tmp_path):
    """A finished ``simulate -o`` of one curve, and its files."""
    out = tmp_path / "sim"
    assert main([*SIMULATE, "--curve", CURVES[0], "-o", str(out)]) == 0
    files = tree(out)
    assert "results.csv" in files and len([f for f in files if f.startswith("traj")]) == 1
    return out, files


@pytest.mark.parametrize("error, status", [(InputError("bad in the middle"), 2),
                                           (KeyboardInterrupt(), 130)])
def test_a_second_simulate_failing_while_writing_leaves_the_first(previous, monkeypatch,
                                                                  capsys, error, status):
    out, files = previous

    def fail(*args, **kwargs):  # after the trajectories, before results.csv
        raise error

    monkeypatch.setattr(simulate_files, "write_geojson", fail)
    assert main([*SIMULATE, "--curve", CURVES[1], "-o", str(out)]) == status
    assert "Traceback" not in capsys.readouterr().err
    assert tree(out) == files  # no trajectory of the second run beside the first's results
    assert sorted(p.name for p in out.parent.iterdir()) == ["sim"]


def test_a_second_simulate_replaces_the_first_whole(previous):
    out, files = previous
    assert main([*SIMULATE, "--curve", CURVES[1], "-o", str(out)]) == 0
    with open(out / "results.csv", newline="") as fh:
        assert [r["curve_id"] for r in csv.DictReader(fh)] == [CURVES[1]]
    (traj,) = (out / "trajectories").iterdir()
    assert traj.name.startswith("P__turn_T_TW_in_0-_TS_out_0~")


def test_simulate_does_not_replace_a_report(previous, tmp_path, capsys):
    out, files = previous
    (out / ".clearance-simulate").rename(out / ".clearance-report")
    (out / ".clearance-report").write_text("clearance report output, layout 1\n")
    assert main([*SIMULATE, "--curve", CURVES[1], "-o", str(out)]) == 2
    assert "holds clearance report's output, not a clearance simulate output" in (
        capsys.readouterr().err)


def test_disk_full_while_writing_exits_2_and_keeps_the_previous(previous, monkeypatch,
                                                                capsys):
    out, files = previous

    def full(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", full)
    assert main([*SIMULATE, "--curve", CURVES[1], "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"error: {out}/trajectories/" in err and ".new-" not in err  # named as in DIR
    assert "No space left on device" in err and "Traceback" not in err
    assert tree(out) == files
    assert sorted(p.name for p in out.parent.iterdir()) == ["sim"]


def test_outputs_have_the_permissions_of_the_umask(tmp_path):
    mask = os.umask(0o022)
    try:
        assert main([*SIMULATE, "--curve", CURVES[0], "-o", str(tmp_path / "s")]) == 0
    finally:
        os.umask(mask)
    modes = {p.relative_to(tmp_path).as_posix(): p.stat().st_mode & 0o777
             for p in tmp_path.rglob("*")}
    assert modes.pop("s") == 0o755 and modes.pop("s/trajectories") == 0o755
    assert modes and set(modes.values()) == {0o644}, modes


# ----------------------------------------------------------- a real small file system


@pytest.fixture
def small_fs(tmp_path):
    """A 1 MB tmpfs mounted at ``tmp_path/mnt`` (skips where mounting is not possible)."""
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    mount = shutil.which("mount")
    if mount is None or subprocess.run(
            [mount, "-t", "tmpfs", "-o", "size=1m,mode=0755", "tmpfs", str(mnt)],
            capture_output=True).returncode != 0:
        pytest.skip("cannot mount a tmpfs here")
    try:
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], check=False)


def test_a_really_full_disk_and_a_read_only_one(small_fs, capsys):
    out = small_fs / "sim"
    assert main([*SIMULATE, "--curve", CURVES[0], "-o", str(out)]) == 0
    files = tree(out)
    filler = small_fs / "filler"
    with open(filler, "wb", buffering=0) as fh:  # fill the file system to the last block
        with pytest.raises(OSError) as exc:
            while True:
                fh.write(b"\0" * 4096)
        assert exc.value.errno == errno.ENOSPC
    capsys.readouterr()
    assert main([*SIMULATE, "--curve", CURVES[1], "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{out}: cannot write in the folder {small_fs}: No space left on device" in err
    assert "Traceback" not in err and tree(out) == files
    # room for the lock, the staging folder and its marker, not for the 31 kB trajectory
    os.truncate(filler, filler.stat().st_size - 16384)
    assert main([*SIMULATE, "--curve", CURVES[1], "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"error: {out}/trajectories/P__" in err and "No space left on device" in err
    assert "Traceback" not in err
    assert tree(out) == files
    assert sorted(p.name for p in small_fs.iterdir()) == ["filler", "sim"]

    filler.unlink()
    subprocess.run(["mount", "-o", "remount,ro", str(small_fs)], check=True)
    assert main([*SIMULATE, "--curve", CURVES[1], "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{out}: cannot write in the folder {small_fs}: Read-only file system" in err
    assert tree(out) == files


def test_errors_while_writing_name_the_output_and_other_errors_pass(tmp_path):
    out = tmp_path / "out"
    with pytest.raises(InputError, match=r"out: cannot write the output \(.*sub\): Perm"):
        with output_folder(out, DEMO) as staging:
            raise PermissionError(errno.EACCES, "Permission denied", str(staging / "sub"))
    with pytest.raises(PermissionError):  # not the output's: left as it is
        with output_folder(out, DEMO):
            raise PermissionError(errno.EACCES, "Permission denied", "/etc/shadow")
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_a_read_only_parent_exits_2_and_keeps_the_previous(previous, monkeypatch, capsys):
    # the real read-only file system is in the tmpfs test; this one runs everywhere
    out, files = previous

    def read_only(*args, **kwargs):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(out.parent / ".sim.new-x"))

    monkeypatch.setattr(output_dir.tempfile, "mkdtemp", read_only)
    assert main([*SIMULATE, "--curve", CURVES[1], "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"error: {out}: cannot write the output" in err and "Read-only file system" in err
    assert "Traceback" not in err and tree(out) == files
    assert sorted(p.name for p in out.parent.iterdir()) == ["sim"]  # the lock is gone too


def test_a_folder_name_of_250_bytes_works_and_one_over_255_is_refused(tmp_path):
    out = tmp_path / ("ü" * 125)  # 250 bytes: its staging name is cut, with a hash
    write_demo(out)
    write_demo(out, "demo,again\n")
    assert (out / "a.txt").read_text() == "demo,again\n"
    assert os.listdir(tmp_path) == [out.name]
    with pytest.raises(InputError, match="longer than 255 bytes"):
        write_demo(tmp_path / ("x" * 256))
