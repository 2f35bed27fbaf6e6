# The .pyi stub names every keyword option the module accepts, no more.
import ast
import os

import ddtscale


def stub_keywords(function):
    stub = os.path.join(os.path.dirname(ddtscale.__file__), "__init__.pyi")
    tree = ast.parse(open(stub).read())
    for node in tree.body:
        if isinstance(node, ast.FunctionDef) and node.name == function:
            return {a.arg for a in node.args.kwonlyargs}
    raise AssertionError(f"{function} is not in the stub")


def test_stub_lists_the_options():
    assert stub_keywords("upscale") == set(ddtscale.UPSCALE_OPTIONS)
    assert stub_keywords("upscale_volume") == set(ddtscale.VOLUME_OPTIONS)
    assert stub_keywords("grid") | {"bounds"} == set(ddtscale.GRID_OPTIONS)
    assert stub_keywords("upscale_sequence") == set(ddtscale.SEQUENCE_OPTIONS)
