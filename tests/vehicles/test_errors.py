"""The error tree (clearance.vehicles.errors): what is bad input, what is one curve's
geometry, what is a bug, and the exit status each gets from the command line."""

from __future__ import annotations

import gzip

import pytest

import clearance
from clearance.networks.loading import load_network
from clearance.reports.cli import main as cli
from clearance.vehicles.errors import (
    ClearanceError,
    GeometryError,
    InputError,
    LimitError,
    NetworkError,
    OptionError,
    RouteError,
    TableError,
)
from clearance.vehicles.table import load_tables


def test_the_tree():
    for source in (TableError, NetworkError, RouteError, OptionError, LimitError):
        assert issubclass(source, InputError) and issubclass(source, ClearanceError)
    assert issubclass(GeometryError, ClearanceError)
    assert not issubclass(GeometryError, InputError)  # a curve's error row, not exit 2
    assert clearance.NetworkError is NetworkError  # the public API names the same classes


def test_an_input_error_says_where_in_its_message_and_attributes():
    e = RouteError("unknown edge 'x'", file="bus.rou.xml", element="route 'r14'")
    assert str(e) == "bus.rou.xml: unknown edge 'x'"
    assert (e.file, e.row, e.element) == ("bus.rou.xml", None, "route 'r14'")
    # a message that already names the file is not prefixed twice
    assert str(InputError("a.csv:3: bad", file="a.csv")) == "a.csv:3: bad"


def test_a_broken_network_is_a_network_error_naming_its_file(tmp_path):
    bad = tmp_path / "bad.net.xml.gz"
    bad.write_bytes(gzip.compress(b"<net><edge id='e'><lane id='e_0' ")[:30])
    with pytest.raises(NetworkError) as info:
        load_network(bad)
    assert info.value.file == str(bad) and str(bad) in str(info.value)


def test_an_unreadable_table_is_a_table_error_naming_its_file(tmp_path):
    bad = tmp_path / "t.csv"
    bad.write_bytes(b"name,\x00units\n")
    with pytest.raises(TableError) as info:
        load_tables([bad])
    assert info.value.file == str(bad)


def test_exit_status_by_kind_of_error(monkeypatch, capsys):
    def failing(exc):
        def run(args):
            raise exc
        return run

    cases = [(OptionError("--bbox '1': give four numbers"), 2),
             (GeometryError("centre line turns back"), 3),   # escaped a study: a bug
             (ClearanceError("libsumo is not available"), 3),
             (ZeroDivisionError("division by zero"), 3)]
    for exc, status in cases:
        monkeypatch.setattr("clearance.reports.cli.vehicles.run", failing(exc))
        assert cli.main(["vehicles"]) == status
        err = capsys.readouterr().err
        assert "Traceback" not in err and str(exc) in err
    # a bug says so in one line, and shows its traceback under -v
    monkeypatch.setattr("clearance.reports.cli.vehicles.run", failing(KeyError("k")))
    assert cli.main(["vehicles"]) == 3
    assert "internal error" in capsys.readouterr().err
    assert cli.main(["-v", "vehicles"]) == 3
    assert "Traceback" in capsys.readouterr().err
