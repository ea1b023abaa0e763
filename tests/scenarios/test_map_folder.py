"""Several papers' maps share one report folder: a map run keeps the other papers' maps."""

from __future__ import annotations

from gyrobench.scenarios.cli.reproduce_map import keep_other_maps
from gyrobench.scenarios.reports.map_section import FIGURES, MAP_FILE, RUN_FILE


def test_a_map_run_keeps_the_other_papers_maps_byte_for_byte_and_nothing_else(tmp_path):
    out, new = tmp_path / "report", tmp_path / "new"
    new.mkdir()
    (new / "fog_vibration").mkdir()  # the paper just mapped, written by the run itself
    (new / "fog_vibration" / MAP_FILE).write_text("{\"new\": 1}\n")
    for name, body in (("rlg_thermal", b"{\"rlg\": [1, 2]}\n"), ("fog_vibration", b"{\"old\": 0}\n")):
        d = out / name
        d.mkdir(parents=True)
        (d / MAP_FILE).write_bytes(body)
        (d / RUN_FILE).write_bytes(b"{\"run\": 1}\n")
        (d / FIGURES[0][0]).write_bytes(b"\x89PNG fake")
        (d / "results.json").write_text("{}")  # a report's file, not the map's
    (out / "ifog_thermal").mkdir()  # a paper without a map
    (out / "ifog_thermal" / "results.json").write_text("{}")

    kept = keep_other_maps(out, new, "fog_vibration")

    assert kept == ["rlg_thermal"]
    assert (new / "rlg_thermal" / MAP_FILE).read_bytes() == b"{\"rlg\": [1, 2]}\n"
    assert (new / "rlg_thermal" / RUN_FILE).read_bytes() == b"{\"run\": 1}\n"
    assert (new / "rlg_thermal" / FIGURES[0][0]).read_bytes() == b"\x89PNG fake"
    assert not (new / "rlg_thermal" / "results.json").exists()
    assert not (new / "ifog_thermal").exists()
    assert (new / "fog_vibration" / MAP_FILE).read_text() == "{\"new\": 1}\n"  # the old map is not kept


def test_no_folder_yet_keeps_nothing(tmp_path):
    (tmp_path / "new").mkdir()
    assert keep_other_maps(tmp_path / "absent", tmp_path / "new", "rlg_thermal") == []
