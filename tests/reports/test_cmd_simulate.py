"""``clearance simulate``: outputs, determinism, summary and bad input."""

from __future__ import annotations

import csv
import io
import json
import os
import subprocess
import xml.etree.ElementTree as ET
from types import SimpleNamespace

import numpy as np
import pytest
from shapely.geometry import LineString, Point

from clearance.networks.samples import build as samples
from clearance.networks.selection import Selection
from clearance.networks.sumo import placement
from clearance.networks.sumo.tools import find_sumo_binary, sumo_home
from clearance.reports.cli.main import main
from clearance.reports.exports.envelopes import VERDICT_RGBA
from clearance.reports.output.file_names import file_name
from clearance.reports.results import simulate_files
from clearance.reports.results.tables import clearance_csv
from clearance.reports.study.run import run_study
from clearance.vehicles.table import bundled_table, load_tables

pytest.importorskip("libsumo")

NET = samples.SAMPLES_DIR / "intersection" / "intersection.net.xml"
TABLE = bundled_table("aashto_green_book")
CURVES = ("turn:X:XN_in_0->XW_out_0", "turn:T:TW_in_0->TS_out_0")
ARGS = ["simulate", "-n", str(NET), "-t", str(TABLE), "--vehicle", "P", "--vehicle",
        "CITY-BUS", "--curve", CURVES[0], "--curve", CURVES[1]]


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    out = tmp_path_factory.mktemp("sim")
    first, second = out / "a", out / "b"
    assert main([*ARGS, "-o", str(first), "--fcd"]) == 0
    assert main([*ARGS, "-o", str(second)]) == 0
    return first, second


def _results(folder):
    with open(folder / "results.csv", newline="") as fh:
        return {(r["vehicle"], r["curve_id"]): r for r in csv.DictReader(fh)}


def test_results_hold_the_designed_verdicts(outputs):
    rows = _results(outputs[0])
    assert list(next(iter(rows.values())))[: len(simulate_files.RESULT_COLUMNS)] == list(
        simulate_files.RESULT_COLUMNS)
    # the designed verdicts are the lane's; a bus that cuts X's NW curb on its lane
    # swings into the two opposing lanes and stays paved; one that cannot make the T on
    # its lane swings wide into the opposing lane and makes it
    lane = {k: r["lane_verdict"] for k, r in rows.items()}
    assert lane[("P", CURVES[0])] == "clear" == rows[("P", CURVES[0])]["verdict"]
    assert rows[("P", CURVES[0])]["path"] == "lane"
    assert lane[("CITY-BUS", CURVES[0])] == "fails"
    nw = rows[("CITY-BUS", CURVES[0])]
    assert (nw["verdict"], nw["path"], nw["encroaches_on"]) == (
        "encroaches", "swung", "opposing lanes")
    bus = rows[("CITY-BUS", CURVES[1])]
    assert lane[("CITY-BUS", CURVES[1])] == "cannot-turn"
    assert (bus["verdict"], bus["path"], bus["encroaches_on"]) == (
        "encroaches", "swung", "opposing lanes")
    assert "into the opposing lanes" in bus["reason"]
    assert "on the lane centre line: cannot-turn" in bus["reason"]
    for r in rows.values():
        assert float(r["sumo_max_deviation_m"]) < 1e-4
        assert int(r["sumo_steps"]) > 100
        assert (float(r["margin_m"]) >= 0) == (r["verdict"] == "clear")
    bus = rows[("CITY-BUS", CURVES[0])]
    # the bus offtracks more than half a metre on a 9.5 m corner and sweeps over 3 m
    assert float(bus["max_offtracking_m"]) > 0.5
    assert 3.0 < float(bus["swept_width_m"]) < 8.0


def test_outputs_are_byte_identical_between_runs(outputs):
    a, b = outputs
    for name in ("envelopes.geojson",):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    # with --fcd (a) SUMO places a swung run along its swung path, not its lane's: only its
    # count of SUMO steps differs
    with_fcd, without = _results(a), _results(b)
    assert list(with_fcd) == list(without)
    for key, row in with_fcd.items():
        if row["path"] == "swung":
            del row["sumo_steps"], without[key]["sumo_steps"]
    assert with_fcd == without
    files = sorted(p.name for p in (a / "trajectories").iterdir())
    assert files == sorted(p.name for p in (b / "trajectories").iterdir())
    assert len(files) == 4 and "CITY-BUS__turn_X_XN_in_0-_XW_out_0~f63c83019f58a091.csv" in files
    for f in files:
        assert (a / "trajectories" / f).read_bytes() == (b / "trajectories" / f).read_bytes()


def test_geojson_envelopes_in_local_metres(outputs):
    doc = json.loads((outputs[0] / "envelopes.geojson").read_text())
    assert "local metres" in doc["coordinate_system"]  # the sample has no projection
    assert len(doc["features"]) == 4
    feat = next(f for f in doc["features"]
                if f["properties"]["vehicle"] == "P" and f["properties"]["curve_id"] == CURVES[0])
    assert feat["properties"]["verdict"] == "clear"
    ring = np.array(feat["geometry"]["coordinates"][0])
    # junction X is centred on the origin: the car's turn lies in its NW quadrant
    assert ring[:, 0].min() > -60 and ring[:, 0].max() < 5
    assert ring[:, 1].min() > -5 and ring[:, 1].max() < 60


def test_trajectory_csv_starts_on_the_centre_line(outputs):
    name = file_name(["P", CURVES[0]], ".csv")
    text = (outputs[0] / "trajectories" / name).read_text()
    lines = text.splitlines()
    assert lines[0].split(",")[:4] == ["t_s", "s_m", "x_m", "y_m"]
    first = dict(zip(lines[0].split(","), map(float, lines[1].split(",")), strict=True))
    last = dict(zip(lines[0].split(","), map(float, lines[-1].split(",")), strict=True))
    # the front axle starts on the approach lane's centre (x = -4.88) heading south
    assert first["xf_m"] == pytest.approx(-4.88, abs=1e-3) and first["t_s"] == 0.0
    assert first["theta_rad"] == pytest.approx(-np.pi / 2, abs=1e-3)
    # and leaves heading west after the right turn
    assert abs(last["theta_rad"] % (2 * np.pi) - np.pi) < 0.05


def test_fcd_and_replay_config(outputs, capsys):
    a, b = outputs
    fcd = (a / "fcd.xml").read_text()
    assert "<timestep" in fcd and 'id="v0"' in fcd
    assert 'net-file value="' in (a / "replay.sumocfg").read_text()
    assert not (b / "fcd.xml").exists()
    assert not list(a.glob(".*tmp"))


def _fcd_points(fcd, vid):
    """The FCD's (x, y) of vehicle ``vid``, step by step."""
    root = ET.parse(fcd).getroot()
    return np.array([(float(v.get("x")), float(v.get("y"))) for ts in root.iter("timestep")
                     for v in ts.iter("vehicle") if v.get("id") == vid])


def test_paths_drawn_for_sumo_gui_are_the_replayed_ones(outputs):
    a, _ = outputs
    assert 'additional-files value="paths.add.xml"' in (a / "replay.sumocfg").read_text()
    rows = _results(a)
    polys = ET.parse(a / "paths.add.xml").getroot().findall("poly")
    assert len(polys) == len(rows) == 4
    deviations = {}
    for poly in polys:
        params = {p.get("key"): p.get("value") for p in poly.findall("param")}
        row = rows[(params["vehicle"], params["curve_id"])]
        assert (params["verdict"], params["path"]) == (row["verdict"], row["path"])
        assert params["point"] == "front-bumper centre"
        assert poly.get("fill") == "0" and float(poly.get("lineWidth")) < 0.5
        assert poly.get("type") == f"path:{row['verdict']}"
        rgb = tuple(int(c) for c in poly.get("color").split(","))[:3]
        assert rgb == VERDICT_RGBA[row["verdict"]][:3]
        # the line drawn is where the replay's point of that run goes
        line = LineString([tuple(map(float, xy.split(","))) for xy in poly.get("shape").split()])
        shown = _fcd_points(a / "fcd.xml", params["sumo_vehicle"])
        assert len(shown) == int(row["sumo_steps"])
        deviations[params["vehicle"], params["curve_id"]] = max(
            line.distance(Point(p)) for p in shown)
    assert max(deviations.values()) < 0.02, deviations  # the FCD keeps 2 decimals


def test_paths_and_replay_config_load_in_sumo(outputs, tmp_path):
    a, _ = outputs
    sumo = str(find_sumo_binary("sumo"))
    env = {**os.environ, "SUMO_HOME": str(sumo_home())}  # SUMO_HOME: validated by the XSD
    for args in (["-n", str(NET), "-a", str(a / "paths.add.xml")],
                 ["-c", str(a / "replay.sumocfg")]):
        proc = subprocess.run([sumo, *args, "--end", "1", "--xml-validation", "always",
                               "--no-step-log"], capture_output=True, text=True, env=env,
                              cwd=tmp_path, timeout=120)
        assert proc.returncode == 0, (args, proc.stderr)


def test_the_printed_replay_command_runs_after_a_pip_install(outputs, tmp_path):
    # a fresh shell of a pip install: no SUMO_HOME, no activated venv on PATH
    a, _ = outputs
    env = {k: v for k, v in os.environ.items() if k not in ("SUMO_HOME", "VIRTUAL_ENV")}
    env["PATH"] = "/usr/bin:/bin"
    command = placement.replay_command(a / "replay.sumocfg", a / "fcd.xml")
    # --help: fcdReplay.py parses its options and exits before it opens sumo-gui (which
    # needs a display); it gets that far only with SUMO_HOME's sumolib and traci
    for cmd in (command + " --help", f"sh {a / 'replay.sh'} --help"):
        proc = subprocess.run(["sh", "-c", cmd], capture_output=True, text=True, env=env,
                              cwd=tmp_path, timeout=120)
        assert proc.returncode == 0, (cmd, proc.stderr)
        assert "--fcd-files" in proc.stdout
    assert os.access(a / "replay.sh", os.X_OK)
    # the same command without SUMO_HOME, as printed before: it fails
    bare = command.split(" ", 1)[1]
    proc = subprocess.run(["sh", "-c", bare + " --help"], capture_output=True, text=True,
                          env=env, cwd=tmp_path, timeout=120)
    assert proc.returncode != 0


def test_summary_printed(tmp_path, capsys):
    assert main([*ARGS[:-4], "--curve", CURVES[1], "--no-sumo", "--lane-only"]) == 0
    out = capsys.readouterr().out
    assert "2 run(s): 1 cannot-turn, 1 fails" in out
    assert out.index("CITY-BUS") < out.index("\nP ")  # worst first


def test_selection_by_junction_and_box(capsys):
    base = ["simulate", "-n", str(NET), "-t", str(TABLE), "--vehicle", "P", "--no-sumo"]
    assert main([*base, "--junction", "T"]) == 0
    assert "4 run(s)" in capsys.readouterr().out  # the four turns of the T junction
    # a box round the X junction's centre only
    from clearance.networks.reader import read_network

    x = read_network(NET).junctions["X"]
    box = f"{x.x - 3},{x.y - 3},{x.x + 3},{x.y + 3}"
    assert main([*base, f"--bbox={box}", "--kind", "turn"]) == 0  # '=': XMIN may be < 0
    out = capsys.readouterr().out
    assert "turn:X:" in out and "turn:T:" not in out


@pytest.mark.parametrize("extra, message", [
    (["--vehicle", "WB-41"], "unknown vehicle 'WB-41'; did you mean 'WB-40'"),
    (["--curve", "turn:X:XN_in_0->XW_out_1"],
     "unknown curve 'turn:X:XN_in_0->XW_out_1'; did you mean 'turn:X:XN_in_0->XW_out_0'"),
    (["--clearance", "-1"], "--clearance must be a length >= 0 m"),
    (["--fcd"], "--fcd needs an output folder"),
    (["--sumo-step", "0.15"], "the SUMO step (0.15 s) must be a whole multiple"),
    (["--sumo-step", "0"], "the SUMO step must be a positive number"),
    (["--junction", "TX"], "--junction 'TX': no such junction in"),
    (["--bbox=1e6,1e6,1e6,1e6"], "no curve passes the selection (kind turn, "),
])
def test_bad_input_exits_2(extra, message, capsys):
    args = ["simulate", "-n", str(NET), "-t", str(TABLE), "--vehicle", "P", *extra]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_missing_network_exits_2(tmp_path, capsys):
    assert main(["simulate", "-n", str(tmp_path / "none.net.xml"), "--vehicle", "P"]) == 2
    assert "none.net.xml" in capsys.readouterr().err


def test_trajectory_file_names_are_safe_and_unique():
    runs = [SimpleNamespace(vehicle=SimpleNamespace(name=n), curve=SimpleNamespace(curve_id=c))
            for n, c in (("a b", "turn:J"), ("a_b", "turn_J"), ("car", "bend7"),
                         ("car", ".."))]
    names = simulate_files.trajectory_files(runs)
    assert len(set(names)) == 4
    assert names[2] == "car__bend7.csv"  # nothing to change: the ids themselves
    assert names[0].startswith("a_b__turn_J~") and names[0].endswith(".csv")
    assert names[1] == "a_b__turn_J.csv"  # "a_b", "turn_J" as they are; "a b" was changed
    assert names[3].startswith("car__") and "/" not in names[3]



def test_a_run_that_crashes_sumo_fails_alone_and_the_others_are_driven():
    from clearance.analysis.tracking import TrackingSettings
    from clearance.networks.curves import extract_curves
    from clearance.networks.driving.drive import DriveOptions
    from clearance.networks.reader import read_network
    from clearance.reports.study.drives import drive_in_workers
    from clearance.vehicles.table import bundled_table_paths, load_tables
    from tests.reports.test_executor import CrashingExecutor

    net = read_network(NET)
    curves = extract_curves(net)[:6]
    car = load_tables(bundled_table_paths(), ["P"]).vehicles()[0]
    pairs = [(car, c) for c in curves]
    victim = curves[2].curve_id
    runs = drive_in_workers(net, pairs, TrackingSettings(), DriveOptions(),
                            executor=CrashingExecutor(2, victim))
    assert [r.curve.curve_id for r in runs] == [c.curve_id for c in curves]
    for r in runs:
        if r.curve.curve_id == victim:
            assert r.verdict == "error" and "worker process died" in r.reason
        else:
            assert r.error == "" and r.verdict in ("clear", "encroaches", "fails", "cannot-turn")


#: Columns results.csv shares with clearance.csv: the verdicts, the path and the design
#: feedback (clearance.reports.results.feedback), which the two commands must fill alike.
SHARED = ("verdict", "margin_m", "paved_margin_m", "max_offtracking_m", "swept_width_m",
          "lane_verdict", "lane_margin_m", "path", "encroaches_on", "reason", "serves_up_to",
          "serves_encroaching_up_to", "overreach_station_m", "overreach_x", "overreach_y",
          "extra_width_m")


def test_results_carry_the_design_feedback_of_clearance_report(tmp_path):
    vehicles = ["P", "CITY-BUS", "WB-62"]
    out = tmp_path / "sim"
    args = ["simulate", "-n", str(NET), "--junction", "T", "-o", str(out), "--workers", "1"]
    for v in vehicles:
        args += ["--vehicle", v]
    assert main(args) == 0
    sim = _results(out)
    assert set(SHARED) <= set(simulate_files.RESULT_COLUMNS)
    study = run_study([NET], load_tables(None, vehicles), workers=1,
                      selection=Selection(junctions=("T",)))
    report = {(r["vehicle"], r["curve_id"]): r
              for r in csv.DictReader(io.StringIO(clearance_csv(study)))}
    assert sim.keys() == report.keys() and len(sim) == 12
    for key, r in report.items():
        for c in SHARED:
            a, b = sim[key][c], r[c]
            if c.endswith("_m") or c in ("overreach_x", "overreach_y"):
                assert (a == "") == (b == ""), (key, c, a, b)
                if a:
                    assert float(a) == pytest.approx(float(b), abs=1e-9), (key, c)
            else:
                assert a == b, (key, c, a, b)
    # the feedback is there to compare: every run not clear has its worst overreach (said
    # in its reason too), the clear ones none; the T serves up to the bus staying paved
    for r in sim.values():
        has = bool(r["extra_width_m"])
        assert has == (r["verdict"] in ("fails", "encroaches")), r
        assert ("more width there" in r["reason"]) == has
        if has:
            assert float(r["extra_width_m"]) > 0
            assert float(r["overreach_station_m"]) >= 0
    assert {r["serves_encroaching_up_to"] for r in sim.values()} >= {"CITY-BUS"}
    assert any(r["verdict"] == "fails" for r in sim.values())


def test_a_curve_whose_lanes_do_not_admit_the_vehicle_is_not_driven(tmp_path, capsys,
                                                                    bus_street_net):
    # as in a study: P is not driven from a bus-only street (SUMO would refuse to place
    # it, an error row), the bus is, and the summary says how many runs were left out
    net = bus_street_net
    out = tmp_path / "sim"
    assert main(["simulate", "-n", str(net), "--vehicle", "P", "--vehicle", "CITY-BUS",
                 "--no-sumo", "-o", str(out)]) == 0
    rows = _results(out)
    assert ("CITY-BUS", "turn:X:WX_0->XN_0") in rows
    assert ("P", "turn:X:WX_0->XN_0") not in rows
    assert ("P", "turn:X:SX_0->XN_0") in rows
    assert all(r["verdict"] != "error" for r in rows.values())
    assert "1 run(s) not permitted" in capsys.readouterr().out
    # only P on the bus street: nothing to drive is bad input, named
    status = main(["simulate", "-n", str(net), "--vehicle", "P", "--curve",
                   "turn:X:WX_0->XN_0", "-o", str(tmp_path / "none")])
    assert status == 2
    err = capsys.readouterr().err
    assert "no selected curve admits" in err and "passenger" in err
    assert not (tmp_path / "none" / "results.csv").exists()


def test_paths_additional_greys_errors_and_skips_unmodelled_runs():
    t = np.linspace(0.0, 1.0, 11)
    trajectory = SimpleNamespace(xf_m=10.0 * t, yf_m=0.0 * t, theta_rad=0.0 * t)
    run = SimpleNamespace(trajectory=trajectory, vehicle=SimpleNamespace(front_overhang_m=1.0))

    def driven(verdict, chosen, error=""):
        return SimpleNamespace(
            chosen_run=chosen, vehicle=SimpleNamespace(name="bus 1"),
            curve=SimpleNamespace(curve_id="turn:J", kind="turn"), verdict=verdict,
            path="lane", swing_m=0.0, error=error, sumo_vehicle="v0",
            result=SimpleNamespace(margin_m=-0.25))

    runs = [driven("fails", run), driven("error", run, "SUMO lost it"), driven("clear", None)]
    root = ET.fromstring(simulate_files.paths_additional(runs, "net"))
    first, second = root.findall("poly")  # the run never modelled is left out
    assert (first.get("id"), second.get("id")) == ("path:bus_1:turn_J", "path:bus_1:turn_J~2")
    assert first.get("color") == "220,0,0,255" and second.get("color") == "128,128,128,255"
    assert second.get("type") == "path:error"
    # the front-bumper centre's path: the front axle's ahead by the front overhang
    assert first.get("shape") == "1.000,0.000 11.000,0.000"
    params = [{p.get("key"): p.get("value") for p in poly.findall("param")}
              for poly in (first, second)]
    assert params[0]["margin_m"] == "-0.250" and "margin_m" not in params[1]
    assert params[0]["point"] == "front-bumper centre" and params[0]["network"] == "net"
