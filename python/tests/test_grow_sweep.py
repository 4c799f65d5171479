"""softway.grow_sweep: growth studies at several speeds, serially and on a Dask LocalCluster
of two worker processes: the same Dataset, bit for bit, and each point's numbers those of
softway.grow with the point's speed; a point with a bad value is reported, the other kept;
a point's checkpoint lets the sweep go on to more passes.

The study: scenarios/polygon.toml shrunk as test_grow.py shrinks it (96 rim nodes, h =
1e-5 s), 2 passes, at omega = 250 and 300 rad/s."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

import softway
from test_grow import POLYGON, SHRINK, is_timing

PASSES = 2
OMEGAS = [250.0, 300.0]


def shrunk():
    return softway.Scenario(POLYGON).with_values(**SHRINK)


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    """The 2-speed growth sweep serially and on a 2-process LocalCluster, and the two
    studies by softway.grow."""
    from dask.distributed import Client, LocalCluster

    d = tmp_path_factory.mktemp("grow_sweep")
    grid = {"rolling.omega": OMEGAS}
    serial = softway.grow_sweep(shrunk(), grid, passes=PASSES, executor="serial",
                                out=d / "serial", progress=False)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        dist = softway.grow_sweep(shrunk(), grid, passes=PASSES,
                                  executor=client.get_executor(), out=d / "dask",
                                  progress=False)
    singles = [
        softway.grow(shrunk(), passes=PASSES, out=d / f"single-{w}", progress=False,
                     **{"rolling.omega": w})
        for w in OMEGAS
    ]
    return d, serial, dist, singles


def test_the_same_dataset_on_any_executor(swept):
    d, serial, dist, _ = swept
    assert serial.identical(dist)
    # Bit for bit, NaN included: every numeric variable's bytes.
    for name, v in serial.variables.items():
        if v.dtype.kind == "f":
            assert v.values.tobytes() == dist[name].values.tobytes(), name
    # Written as NetCDF by each, and read back the same.
    for sub, ds in (("serial", serial), ("dask", dist)):
        back = xr.load_dataset(d / sub / "grow_sweep.nc")
        for name in ("rms_m", "level_db", "rate_db_per_1e5", "fastest_band_frequency_hz"):
            assert back[name].values.tobytes() == ds[name].values.tobytes(), (sub, name)
    # Each point's study written by its worker in its own folder, checkpoint included.
    for sub in ("serial", "dask"):
        for w in OMEGAS:
            folder = d / sub / f"rolling.omega={w}"
            ck = json.loads((folder / "checkpoint.json").read_text())
            assert len(ck["passes"]) == PASSES


def test_each_point_is_softway_grow_at_its_speed(swept):
    d, ds, _, singles = swept
    assert list(ds["rolling.omega"].values) == OMEGAS
    assert ds.sizes["pass"] == PASSES and ds.sizes["after_passes"] == PASSES + 1
    assert ds["level_db"].dims == ("rolling.omega", "after_passes", "wavelength")
    assert (ds["error"].values == "").all() and not ds["interrupted"].values.any()
    assert ds.attrs["softway_failed_points"] == 0
    for i, g in enumerate(singles):
        pt = ds.isel({"rolling.omega": i})
        # The per-pass scalars, less the wall-clock columns (left out of the Dataset).
        kept = [n for n in g.passes.data_vars if not is_timing(n)]
        assert kept and all(not is_timing(n) for n in kept)
        for name in g.passes.data_vars:
            if is_timing(name):
                assert name not in ds
            else:
                assert pt[name].values.tobytes() == g.passes[name].values.tobytes(), name
                assert pt[name].attrs["units"] == g.passes[name].attrs["units"]
        # The band table.
        assert ds["wavelength"].values.tobytes() == g.bands["wavelength"].values.tobytes()
        assert pt["level_db"].values.tobytes() == g.bands["level_db"].values.tobytes()
        assert (pt["rate_db_per_1e5"].values.tobytes()
                == g.bands["rate_db_per_1e5"].values.tobytes())
        assert (pt["band_frequency_hz"].values.tobytes()
                == g.bands["frequency_hz"].values.tobytes())
        # The fastest band: the summary's, and the band of the largest rate.
        fb = g.summary["fastest_band"]
        assert float(pt["fastest_band_centre_wavelength_m"]) == fb["centre_wavelength_m"]
        assert float(pt["fastest_band_frequency_hz"]) == fb["frequency_hz"]
        rates = g.bands["rate_db_per_1e5"].values
        j = int(np.nanargmax(rates))
        assert fb["centre_wavelength_m"] == g.bands["wavelength"].values[j]
        assert float(pt["rms_final_m"]) == g.summary["rms_final_m"]
    # An independent check of the frequencies: V / wavelength, V = omega R grows with omega.
    v = ds["speed_m_s"].values
    assert v[1] / v[0] == pytest.approx(OMEGAS[1] / OMEGAS[0], rel=1e-12)
    assert np.allclose(ds["band_frequency_hz"].values,
                       v[:, None] / ds["wavelength"].values[None, :], rtol=1e-9)


def test_a_failed_point_is_reported_and_the_other_kept(tmp_path, swept):
    """A value the validation refuses is refused before any study runs (ScenarioError,
    its dotted key); a study that fails where it runs (its folder cannot be claimed: a
    file stands where `out/<key>=<value>` goes) is reported, the other kept."""
    _, serial, _, _ = swept
    with pytest.raises(softway.ScenarioError) as e:
        softway.grow_sweep(shrunk(), {"rolling.omega": [OMEGAS[0], "fast"]},
                           passes=PASSES, executor="serial", progress=False)
    assert e.value.key == "rolling.omega"
    out = tmp_path / "f"
    out.mkdir()
    (out / f"rolling.omega={OMEGAS[1]!r}").write_text("a file where the study goes")
    grid = {"rolling.omega": OMEGAS}
    with pytest.warns(RuntimeWarning, match=r"grow_sweep point .* failed"):
        ds = softway.grow_sweep(shrunk(), grid, passes=PASSES, out=out,
                                progress=False)  # the default: a LocalCluster of 2 processes
    assert ds.attrs["softway_failed_points"] == 1
    err = str(ds["error"].values[1])
    assert f"rolling.omega={OMEGAS[1]!r}" in err, err
    assert ds["error"].values[0] == ""
    good = ds.isel({"rolling.omega": 0})
    assert good["rms_m"].values.tobytes() == serial["rms_m"].isel(
        {"rolling.omega": 0}).values.tobytes()
    assert good["level_db"].values.tobytes() == serial["level_db"].isel(
        {"rolling.omega": 0}).values.tobytes()
    bad = ds.isel({"rolling.omega": 1})
    assert np.isnan(bad["rms_m"].values).all() and np.isnan(bad["level_db"].values).all()
    assert math.isnan(float(bad["fastest_band_frequency_hz"]))
    # A growth study's speed in m/s (its name ends in "_s", which is not its unit).
    assert ds["speed_m_s"].attrs["units"] == "m/s"
    assert ds["rolling.omega"].attrs["units"] == "rad/s"


def test_resume_goes_on_from_each_points_checkpoint(tmp_path, swept):
    """A sweep of 1 pass, then resume=True to 2: the bits of the 2-pass sweep; each point
    runs only the pass left."""
    _, serial, _, _ = swept
    out = tmp_path / "r"
    grid = {"rolling.omega": OMEGAS}
    one = softway.grow_sweep(shrunk(), grid, passes=1, executor="serial", out=out,
                             progress=False)
    assert one.sizes["pass"] == 1
    two = softway.grow_sweep(shrunk(), grid, passes=PASSES, executor="serial", out=out,
                             resume=True, progress=False)
    for name in ("rms_m", "uniform_loss_m", "mean_force_n", "level_db", "rate_db_per_1e5"):
        assert two[name].values.tobytes() == serial[name].values.tobytes(), name
    with pytest.raises(ValueError, match="resume=True needs out"):
        softway.grow_sweep(shrunk(), grid, passes=1, resume=True, executor="serial")
    with pytest.raises(ValueError, match="grid_mode"):
        softway.grow_sweep(shrunk(), grid, grid_mode="diagonal", executor="serial")
    assert "fastest band" in softway.grow_sweep.__doc__
