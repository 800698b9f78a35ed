"""cli.main frees what a command left in reference cycles before it returns.

A notebook that runs a command (the lab chapter runs ``analyze``) lives on after it; the
command's figures are cycles that only the cyclic collector frees.
"""

from __future__ import annotations

import argparse
import gc
import weakref

from dstoolkit import cli


class _Node:
    """An object that will refer to itself."""


def test_main_collects_the_cycles_a_command_left(monkeypatch) -> None:
    left: list[weakref.ref[_Node]] = []

    def command(args: argparse.Namespace) -> int:
        node = _Node()
        node.itself = node  # type: ignore[attr-defined]  # a cycle: refcounting never frees it
        left.append(weakref.ref(node))
        return 0

    parser = argparse.ArgumentParser()
    parser.set_defaults(func=command)
    monkeypatch.setattr(cli, "build_parser", lambda: parser)
    gc.disable()  # no automatic collection may free the cycle by chance
    try:
        assert cli.main([]) == 0
        assert left[0]() is None
    finally:
        gc.enable()
