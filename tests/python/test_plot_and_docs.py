"""allanlot.plot (a matplotlib Figure of deviations with intervals, the eq. (3) fit and its terms,
the PSD), the numpydoc docstrings of every public function, and the type stubs."""
import ast
import inspect
import pathlib

import numpy as np
import pytest

import allanlot

PACKAGE = pathlib.Path(allanlot.__file__).parent


def test_plot_returns_a_figure_of_deviations_fit_and_psd():
    matplotlib = pytest.importorskip("matplotlib")
    sim = allanlot.simulate({"sample_rate_hz": 100, "units": "deg/s",
                             "terms": {"N": 0.01, "B": 0.002}}, duration=600)
    x = sim["gyro_x"]
    oadev = allanlot.deviation(x, "oadev", rate=100, data_type="freq", units="deg/s")
    mtie = allanlot.deviation(x, "mtie", rate=100, data_type="freq", taus="octave")
    fit = allanlot.fit(oadev)
    psd = allanlot.psd(x, rate=100)
    fig = allanlot.plot(oadev, mtie, fit=fit, psd=psd, title="gx")
    assert isinstance(fig, matplotlib.figure.Figure)
    dev_ax, psd_ax = fig.axes
    assert dev_ax.get_xscale() == dev_ax.get_yscale() == psd_ax.get_yscale() == "log"
    assert "deg/s" in dev_ax.get_ylabel() and "Hz" in psd_ax.get_xlabel()
    labels = [t.get_text() for t in dev_ax.get_legend().get_texts()]
    assert "oadev" in labels and any(l.startswith("eq. (3) fit") for l in labels)
    assert any(l.startswith("N = ") for l in labels)  # each detected term drawn alone
    # a term line is the term's own law: N / sqrt(tau)
    n_value = fit["terms"]["value"][list(fit["terms"]["term"]).index("N")]
    line = next(l for l in dev_ax.get_lines() if l.get_label().startswith("N = "))
    t, d = line.get_data()
    np.testing.assert_allclose(d, n_value / np.sqrt(t))
    one = allanlot.plot(oadev)
    assert len(one.axes) == 1 and isinstance(one, matplotlib.figure.Figure)
    with pytest.raises(TypeError, match="Deviation"):
        allanlot.plot(allanlot.oadev(x))
    with pytest.raises(ValueError, match="nothing to plot"):
        allanlot.plot()


def _public_callables():
    for name in allanlot.__all__:
        obj = getattr(allanlot, name)
        if inspect.isfunction(obj):
            yield name, obj
        elif inspect.isclass(obj):
            for attr, member in vars(obj).items():
                if inspect.isfunction(member) and not attr.startswith("_"):
                    yield "%s.%s" % (name, attr), member
    for module in (allanlot.noise, allanlot.ci):
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isfunction(obj):
                yield "%s.%s" % (module.__name__, name), obj


def test_every_public_function_has_a_numpydoc_docstring():
    missing = []
    for name, f in _public_callables():
        doc = inspect.getdoc(f) or ""
        params = [p for p in inspect.signature(f).parameters if p != "self"]
        if params and "Parameters\n----------" not in doc:
            missing.append(name + ": Parameters")
        if "Returns\n-------" not in doc:
            missing.append(name + ": Returns")
    assert not missing, missing


def test_every_statistic_and_formula_cites_its_reference():
    for name in allanlot._allantools.ALLANTOOLS_STATS + (
            "deviation", "gcodev", "edf_greenhall", "edf_simple", "edf_totdev", "edf_mtotdev",
            "confidence_interval", "autocorr_noise_id", "psd2allan", "gradev",
            "frequency2phase", "phase2frequency", "plot", "fit", "psd",
            "adev2psd_piecewise_approx", "psd_piecewise_to_adev"):
        doc = inspect.getdoc(getattr(allanlot, name))
        assert "References\n----------" in doc, name
        assert "SP1065" in doc.split("References")[1], name


def test_stubs_name_every_public_function_with_its_parameters():
    assert (PACKAGE / "py.typed").is_file()
    tree = ast.parse((PACKAGE / "__init__.pyi").read_text())
    stubbed = {}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            stubbed[node.name] = node
        elif isinstance(node, (ast.AnnAssign,)):
            stubbed[node.target.id] = node
        elif isinstance(node, ast.ImportFrom):
            for alias in node.names:
                stubbed[alias.asname or alias.name] = node
    assert set(allanlot.__all__) <= set(stubbed), set(allanlot.__all__) - set(stubbed)
    for name in allanlot.__all__:
        obj, node = getattr(allanlot, name), stubbed[name]
        if inspect.isfunction(obj):
            params = [a.arg for a in node.args.args + node.args.kwonlyargs]
            if node.args.vararg:
                params.insert(0, node.args.vararg.arg)
            assert params == list(inspect.signature(obj).parameters), name
