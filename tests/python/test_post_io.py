"""Reading run files: named dims and string coordinates, lazy masking of failed samples,
the /outputs and /solver_stats groups, both ways of declaring the sample dimension, designs."""
import numpy as np
import pytest

from kanesens_post.io import RunFileError, design, open_run, response, time_index
from post_fixtures import pendulum_saltelli, write_run


@pytest.fixture(scope="module")
def pendulum(tmp_path_factory):
    return pendulum_saltelli(tmp_path_factory.mktemp("p") / "pendulum.h5", n_base=32, nt=21)


def test_named_dims_and_coordinates(pendulum):
    ds = open_run(pendulum)
    assert ds.states.dims == ("sample", "time", "state")
    assert ds.sensitivities.dims == ("sample", "time", "state", "sensitivity")
    assert ds.multipliers.dims == ("sample", "time", "constraint")
    assert list(ds.state.values) == ["pivot.q", "pivot.u"]
    assert list(ds.sensitivity.values) == ["L", "m", "pivot.q0"]
    assert ds.output_energy.dims == ("sample", "time")
    assert ds.solver_stats_steps.dims == ("sample",)
    assert ds.attrs["sampling_method"] == "saltelli"
    assert "vary:" in ds.attrs["study_yaml"]
    q = ds.states.sel(state="pivot.q")
    np.testing.assert_allclose(q.isel(sample=0, time=0), ds.parameters.values[0, 2])


def test_failed_samples_are_nan_and_reads_are_lazy(pendulum):
    ds = open_run(pendulum)
    assert not ds.states.variable._in_memory            # nothing read yet
    status = ds.status.values
    assert (status[[5, 77]] == -4).all() and ds.message.values[5].startswith("CV_CONV")
    assert np.isnan(ds.states.values[5]).all() and np.isnan(ds.output_energy.values[77]).all()
    assert np.isfinite(ds.states.values[status == 1]).all()
    # inputs and counters of a failed sample stay readable
    assert np.isfinite(ds.parameters.values[5]).all() and ds.solver_stats_steps.values[5] > 0
    # an indexed read masks the same rows
    assert np.isnan(ds.states.isel(sample=[4, 5], time=3).values[1]).all()
    assert np.isnan(ds.sensitivities.isel(sample=5, time=2).values).all()


def test_sample_dimension_without_coordinate(tmp_path):
    path = write_run(tmp_path / "r.h5", time=[0.0, 1.0], state_names=["a.q"],
                     parameter_names=["k"], parameters=[[1.0], [2.0], [3.0]],
                     states=np.arange(6.0).reshape(3, 2, 1), status=[1, -1, 0],
                     sample_scale=False)
    ds = open_run(path)
    assert list(ds.sample.values) == [0, 1, 2]
    y = response(ds, "a.q").values
    assert y[0].tolist() == [0.0, 1.0] and np.isnan(y[1:]).all()


def test_response_and_time_errors(pendulum):
    ds = open_run(pendulum)
    with pytest.raises(RunFileError, match="states are: pivot.q, pivot.u; outputs are: energy"):
        response(ds, "elbow.q")
    with pytest.raises(RunFileError, match="covers t = 0.0 .. 10.0"):
        time_index(ds, 11.0)
    assert time_index(ds, 4.9) == 10


def test_design_from_study(pendulum):
    ds = open_run(pendulum)
    des = design(ds)
    assert des.names == ["L", "m", "pivot.q0"] and des.x.shape == (160, 3)
    assert des.block[:6].tolist() == [0] * 5 + [1] and des.row[:6].tolist() == [0, 1, 2, 3, 4, 0]
    assert des.dists["pivot.q0"].kind == "normal"
    assert des.dists["L"].variance() == pytest.approx(0.1 ** 2 / 12)


def test_not_a_run_file(tmp_path):
    import h5py
    with h5py.File(tmp_path / "x.h5", "w") as f:
        f["time"] = [0.0]
    with pytest.raises(RunFileError, match="no /status"):
        open_run(tmp_path / "x.h5")


def test_file_without_output_groups(tmp_path):
    import h5py
    path = write_run(tmp_path / "g.h5", time=[0.0, 1.0], state_names=["a.q"],
                     parameter_names=["k"], parameters=[[1.0], [2.0]],
                     states=np.zeros((2, 2, 1)))
    with h5py.File(path, "a") as f:
        del f["outputs"], f["solver_stats"]
    ds = open_run(path)
    assert not [v for v in ds.data_vars if v.startswith(("output_", "solver_stats_"))]


def test_design_labels_and_distributions_come_from_the_file(tmp_path):
    """/design_* labels and /vary are what the analyses use: the study text is not read (here
    it has no vary: section at all)."""
    from post_fixtures import saltelli_design, write_run
    x, _, _ = saltelli_design(8, [lambda u: u, lambda u: 2 + u], seed=2)
    vary = {"a": {"dist": "uniform", "low": 0.0, "high": 1.0},
            "b": {"dist": "triangular", "low": 2.0, "mode": 2.5, "high": 3.0}}
    path = write_run(tmp_path / "f.h5", time=[0.0], state_names=["y"], parameter_names=["a", "b"],
                     parameters=x, states=x[:, :1, None], sampling_method="saltelli",
                     study={"kanesens": 1, "vary": vary})
    import h5py
    with h5py.File(path, "r+") as f:
        f.attrs["study_yaml"] = "kanesens: 1\n"
    ds = open_run(path)
    assert ds.attrs["vary"]["b"] == {"distribution": "triangular", "low": 2.0, "mode": 2.5, "high": 3.0}
    des = design(ds)
    assert des.labels == "file"
    assert des.dists["b"].kind == "triangular" and des.dists["b"].mean() == pytest.approx(2.5)
    assert des.row[:4].tolist() == [0, 1, 2, 3] and des.moved[:4].tolist() == [-1, -1, 0, 1]
    assert des.block[4:8].tolist() == [1] * 4


def test_design_of_an_older_file(tmp_path):
    """A file without /vary and the labels: runs in row order, distributions from the study."""
    path = pendulum_saltelli(tmp_path / "old.h5", n_base=8, nt=3, fail=(), legacy=True)
    ds = open_run(path)
    assert "vary" not in ds.attrs and "design_block" not in ds
    des = design(ds)
    assert des.labels == "row order" and des.dists["pivot.q0"].kind == "normal"
    assert des.block[:6].tolist() == [0] * 5 + [1] and des.moved[:5].tolist() == [-1, -1, 0, 1, 2]


def test_fixed_inputs_are_design_columns_but_not_reported(tmp_path):
    """A `fixed` entry of vary: is a column of the design (its AB block row exists) and is
    left out of what the analyses report."""
    from post_fixtures import saltelli_design, write_function_run
    x, _, _ = saltelli_design(4, [lambda u: u, lambda u: 0 * u + 7.0], seed=2)
    vary = {"a": {"dist": "uniform", "low": 0.0, "high": 1.0}, "k": {"dist": "fixed", "value": 7.0}}
    path = write_function_run(tmp_path / "k.h5", x, ["a", "k"], x[:, 0], method="saltelli", vary=vary)
    des = design(open_run(path))
    assert des.columns == ["a", "k"] and des.names == ["a"] and des.x.shape == (16, 1)
    assert des.block_index(4, "Saltelli").shape == (4, 4)
