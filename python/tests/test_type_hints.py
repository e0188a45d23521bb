"""typing.get_type_hints() resolves the annotations of every public function, class and method of seqtopo (the
package's annotations are strings, `from __future__ import annotations`, evaluated in its namespace: a name the
namespace lacks, such as `os` imported as `_os`, fails only when a tool asks)."""

import inspect
import typing

import pytest

import seqtopo


def _public():
    for name in seqtopo.__all__:
        obj = getattr(seqtopo, name)
        if inspect.isfunction(obj):
            yield name, obj
        elif inspect.isclass(obj) and obj.__module__ == seqtopo.__name__:  # the package's own, not pybind11's
            yield name, obj
            for attribute, member in vars(obj).items():
                if attribute.startswith("_") and attribute not in ("__init__", "__call__"):
                    continue
                if inspect.isfunction(member):
                    yield f"{name}.{attribute}", member
                elif isinstance(member, property) and member.fget is not None:
                    yield f"{name}.{attribute}", member.fget


PUBLIC = list(_public())


def test_every_public_function_is_covered():
    names = {name for name, _ in PUBLIC}
    assert {"map_sequence", "write_report", "localize_sequences", "MapRun", "ProgressEvent"} <= names, names


@pytest.mark.parametrize("name,obj", PUBLIC, ids=[name for name, _ in PUBLIC])
def test_type_hints_resolve(name, obj):
    typing.get_type_hints(obj)
