"""Every public API function states what it returns, and the results the docs list all plot (issue 42,
item 6)."""

from __future__ import annotations

import inspect
import typing

import pytest

import pampipe
import pampipe.api as api
from pampipe.errors import InputError
from tests.support.problems import PROBLEMS


def _return_types() -> dict:
    """The names the annotations use, resolved by the imports of pampipe.api's TYPE_CHECKING block."""
    source = inspect.getsource(api)
    block = source.split("if TYPE_CHECKING:", 1)[1].split("\n\n", 1)[0]
    names: dict = {}
    exec(inspect.cleandoc("\n".join(line for line in block.splitlines()[1:])), names)
    return {**vars(api), **names}


def test_every_public_function_is_annotated_with_a_type_that_exists():
    names = _return_types()
    functions = [getattr(api, n) for n in api.__all__ if inspect.isfunction(getattr(api, n))]
    assert len(functions) >= 17
    for function in functions:
        assert "return" in function.__annotations__, function.__name__
        typing.get_type_hints(function, globalns=names)  # every name resolves


def test_plan_returns_what_its_annotation_says():
    plan = pampipe.plan(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    assert typing.get_type_hints(api.plan, globalns=_return_types())["return"] is type(plan)


def test_route_and_export_results_plot_their_documents():
    route = pampipe.route("Net1", from_node="10", to_node="32", friction=0.25)
    figure = route.plot()
    elevation, bore = figure.axes
    document = route.to_dict()["sections"]
    # the bore drawn is each pipe's, in mm; the distance ends at the route's length
    drawn = list(bore.patches[0].get_data().values)
    assert drawn == pytest.approx([s["inner_diameter_m"] * 1e3 for s in document])
    assert elevation.lines[0].get_xdata()[-1] == pytest.approx(sum(s["length_m"] for s in document))
    exported = pampipe.export_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    cycle, stride = exported.plot().axes
    sections = exported.to_dict()["sections"]
    assert [p.get_height() for p in cycle.patches] == pytest.approx([s["cycle_time_s"] for s in sections])
    assert [p.get_height() for p in stride.patches] == pytest.approx([s["stride_m"] * 1e3 for s in sections])
    with pytest.raises(InputError, match="nothing to plot"):
        pampipe.example().plot()
