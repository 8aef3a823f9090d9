"""Opening network files safely: only the named regular file, never a DTD, within the caps."""

from __future__ import annotations

import gzip
import os
import subprocess
from pathlib import Path

import pytest

from clearance.networks.reader import read_network
from clearance.networks.safe_xml import (
    DEFAULT_MAX_BYTES,
    DEFAULT_MAX_ELEMENTS,
    MAX_ELEMENTS_ENV,
    MAX_MB_ENV,
    max_bytes,
    max_elements,
    open_binary,
    scan_prolog,
)
from clearance.networks.samples.sources import SAMPLES_DIR
from clearance.vehicles.errors import InputError
from tests.cli import CLI
from tests.timeouts import within

REPO = Path(__file__).resolve().parents[2]
INTERSECTION = SAMPLES_DIR / "intersection" / "intersection.net.xml"




def with_doctype(tmp_path: Path, system_id: str, name: str = "dt.net.xml") -> Path:
    text = INTERSECTION.read_text()
    p = tmp_path / name
    p.write_text(text.replace("<net ", f'<!DOCTYPE net SYSTEM "{system_id}">\n<net ', 1))
    return p


def test_a_fifo_named_as_the_dtd_is_never_opened(tmp_path):
    # a FIFO blocks whoever opens it until a writer comes: the CLI must finish anyway
    fifo = tmp_path / "dtd.fifo"
    os.mkfifo(fifo)
    net = with_doctype(tmp_path, str(fifo))
    out = tmp_path / "curves.csv"
    proc = subprocess.run(
        [*CLI, "curves", "-n", str(net), "-o", str(out)],
        capture_output=True, text=True, timeout=30, cwd=REPO, check=False)
    assert proc.returncode == 0, proc.stderr
    assert out.read_text().count("\n") > 10  # the network was read in full


def test_a_dtd_is_not_loaded_even_when_it_exists(tmp_path):
    # the DTD would define the entity the document uses; it is not read, so the reference
    # is never expanded into the edge id it defines
    (tmp_path / "net.dtd").write_text('<!ENTITY who "FROM_THE_DTD">')
    text = INTERSECTION.read_text().replace("<net ", '<!DOCTYPE net SYSTEM "net.dtd">\n<net ', 1)
    text = text.replace("</net>", '<edge id="x&who;"/></net>')
    p = tmp_path / "ent.net.xml"
    p.write_text(text)
    net = within(10, read_network, p)
    assert not [e for e in net.edges if "FROM_THE_DTD" in e]
    assert len(net.edges) == len(read_network(INTERSECTION).edges) + 1


def test_a_network_dtd_is_not_fetched(tmp_path):
    # an address on the network: read without asking it (no_network), in time
    p = with_doctype(tmp_path, "http://192.0.2.1/net.dtd")  # TEST-NET-1: never answers
    net = within(20, read_network, p)
    assert len(net.lanes) > 10


def test_parameter_entities_are_refused(tmp_path):
    p = tmp_path / "pe.net.xml"
    p.write_text('<?xml version="1.0"?><!DOCTYPE net [<!ENTITY % ext SYSTEM "/etc/passwd"> '
                 '%ext;]><net/>')
    with pytest.raises(InputError, match=r"pe\.net\.xml: refused.*entities"):
        read_network(p)


@pytest.mark.parametrize("kind", ["fifo", "device", "directory", "symlink-loop", "dangling",
                                  "under-a-file"])
def test_only_regular_files_are_opened(tmp_path, kind):
    p = tmp_path / "x.net.xml"
    if kind == "fifo":
        os.mkfifo(p)
        expected = "is a FIFO, not a regular file"
    elif kind == "device":
        p = Path("/dev/zero")
        expected = "is a character device, not a regular file"
    elif kind == "directory":
        p.mkdir()
        expected = "is a directory, not a regular file"
    elif kind == "symlink-loop":
        os.symlink(tmp_path / "y", p)
        os.symlink(p, tmp_path / "y")
        expected = "cannot be read (Too many levels of symbolic links)"
    elif kind == "dangling":
        os.symlink(tmp_path / "nowhere", p)
        expected = "no such file"
    else:  # a path through a regular file fails even for root
        (tmp_path / "f").write_text("x")
        p = tmp_path / "f" / "x.net.xml"
        expected = "cannot be read (Not a directory)"
    with pytest.raises(InputError) as info:
        within(10, read_network, p)
    assert str(info.value) == f"{p}: {expected}"


def test_caps_default_and_raised_by_environment(monkeypatch):
    monkeypatch.delenv(MAX_MB_ENV, raising=False)
    monkeypatch.delenv(MAX_ELEMENTS_ENV, raising=False)
    assert (max_bytes(), max_elements()) == (DEFAULT_MAX_BYTES, DEFAULT_MAX_ELEMENTS)
    monkeypatch.setenv(MAX_MB_ENV, "2500")
    monkeypatch.setenv(MAX_ELEMENTS_ENV, "12000000")
    assert (max_bytes(), max_elements()) == (2_500_000_000, 12_000_000)
    for bad in ("lots", "-1", "0", "nan", "1e400"):
        monkeypatch.setenv(MAX_MB_ENV, bad)
        with pytest.raises(InputError, match=f"{MAX_MB_ENV}='{bad}': expected a positive"):
            max_bytes()


def test_a_plain_file_over_the_byte_cap_is_refused_before_reading(tmp_path, monkeypatch):
    monkeypatch.setenv(MAX_MB_ENV, "0.01")  # 10,000 bytes; the sample has about 22,000
    with pytest.raises(InputError) as info:
        read_network(INTERSECTION)
    msg = str(info.value)
    assert msg.startswith(f"{INTERSECTION}: refused: the file's size exceeds the limit of "
                          "0.01 MB")
    assert f"set the environment variable {MAX_MB_ENV} higher" in msg
    monkeypatch.setenv(MAX_MB_ENV, "0.03")
    assert len(read_network(INTERSECTION).lanes) > 10


def connection_bomb(path: Path, n: int) -> Path:
    """A gzip network of ``n`` connections between two edges (it compresses ~300:1)."""
    head = (b'<net version="1.20"><location netOffset="0,0"/>'
            b'<edge id="a" from="J" to="K"><lane id="a_0" index="0" length="10" '
            b'shape="0,0 10,0"/></edge>')
    row = b'<connection from="a" to="a" fromLane="0" toLane="0" dir="t"/>\n'
    with gzip.open(path, "wb", compresslevel=9) as fh:
        fh.write(head)
        for _ in range(n // 10000):
            fh.write(row * 10000)
        fh.write(b"</net>")
    return path


def test_a_decompression_bomb_stops_at_the_element_cap(tmp_path, monkeypatch):
    bomb = connection_bomb(tmp_path / "bomb.net.xml.gz", 200_000)
    assert bomb.stat().st_size < 100_000
    monkeypatch.setenv(MAX_ELEMENTS_ENV, "50000")
    with pytest.raises(InputError) as info:
        read_network(bomb)
    assert str(info.value) == (
        f"{bomb}: refused: the number of elements exceeds the limit of 50,000 elements, far "
        "more than a plausible network needs (a corrupt file or a decompression bomb?); to "
        f"read it anyway, set the environment variable {MAX_ELEMENTS_ENV} higher")
    monkeypatch.setenv(MAX_ELEMENTS_ENV, "300000")  # raised: read in full
    assert len(read_network(bomb).connections) == 200_000


def test_a_decompression_bomb_stops_at_the_byte_cap(tmp_path, monkeypatch):
    bomb = connection_bomb(tmp_path / "bomb.net.xml.gz", 200_000)  # 12.8 MB unpacked
    monkeypatch.setenv(MAX_MB_ENV, "5")
    with pytest.raises(InputError, match=r"bomb\.net\.xml\.gz: refused: its decompressed size "
                                         r"exceeds the limit of 5 MB.*CLEARANCE_MAX_MB"):
        read_network(bomb)


def test_truncated_gzip_and_truncated_xml(tmp_path):
    data = gzip.compress(INTERSECTION.read_bytes())
    gz = tmp_path / "cut.net.xml.gz"
    gz.write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError, match=r"cut\.net\.xml\.gz: (cannot be decompressed|"
                                         r"truncated or corrupt)"):
        read_network(gz)
    plain = tmp_path / "cut.net.xml"
    plain.write_bytes(INTERSECTION.read_bytes()[:15000])
    with pytest.raises(InputError, match=r"cut\.net\.xml: malformed or truncated XML"):
        read_network(plain)


def test_encodings_bom_and_wrong_declarations(tmp_path):
    text = INTERSECTION.read_bytes()
    bom = tmp_path / "bom.net.xml"
    bom.write_bytes(b"\xef\xbb\xbf" + text)
    assert scan_prolog(bom) == "net"
    assert set(read_network(bom).lanes) == set(read_network(INTERSECTION).lanes)
    # declared UTF-16, written in UTF-8
    lie = tmp_path / "lie.net.xml"
    lie.write_bytes(text.replace(b'encoding="UTF-8"', b'encoding="UTF-16"', 1))
    assert lie.read_bytes() != text
    with pytest.raises(InputError, match=r"lie\.net\.xml"):
        read_network(lie)
    # Latin-1 bytes in a UTF-8 file
    latin = tmp_path / "latin.net.xml"
    latin.write_bytes(text.replace(b'id=":T_0"', b'id=":T\xe9_0"', 1))
    with pytest.raises(InputError, match=r"latin\.net\.xml: malformed or truncated XML"):
        read_network(latin)
    # UTF-16 throughout, as declared: read like the original
    utf16 = tmp_path / "utf16.net.xml"
    utf16.write_bytes(text.decode().replace('encoding="UTF-8"', 'encoding="UTF-16"', 1)
                      .encode("utf-16"))
    with pytest.raises(InputError, match=r"utf16\.net\.xml: not XML"):
        scan_prolog(utf16)  # the prolog scanner reads bytes: refused, with the file named


def test_open_binary_is_the_only_door(tmp_path):
    # gzip is recognised by its magic bytes, whatever the name
    p = tmp_path / "plain-name.xml"
    p.write_bytes(gzip.compress(b"<net/>"))
    with open_binary(p) as fh:
        assert fh.read() == b"<net/>"
