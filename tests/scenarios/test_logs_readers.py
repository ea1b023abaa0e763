"""CSV readers of ``scenarios.logs`` for the logs people have: rostopic echo -p, decimal commas, duplicate names."""


import numpy as np
import pytest
from gyrobench.scenarios.logs import read_csv_log

from tests.scenarios.test_cli import assert_one_line_error, run


@pytest.mark.parametrize(
    ("header", "named"),
    [
        ("time [s],gyro [dps],gyro [deg/h]", "'gyro' (columns 1, 2)"),
        ("time [s],gx,gy,gx,gy", "'gx' (columns 1, 3); 'gy' (columns 2, 4)"),
    ],
)
def test_duplicate_header_names_are_refused_naming_them(tmp_path, capsys, rng, header, named):
    ncols = header.count(",") + 1
    data = np.column_stack([np.arange(200) / 100.0, rng.standard_normal((200, ncols - 1))])
    p = tmp_path / "g.csv"
    np.savetxt(p, data, delimiter=",", header=header, comments="")
    with pytest.raises(ValueError, match="names " + named.replace("(", r"\(").replace(")", r"\)") + " more than once"):
        read_csv_log(p, ["1"], None, "deg/s")
    code, _, err = run(["allan", p, "--column", "1", "--units", "deg/s"], capsys)
    assert_one_line_error(code, err, f"names {named} more than once: rename the duplicates")
