"""What every layer shares: input checks, the memory budget and output files.

This is the bottom layer of the package after :mod:`dstoolkit.errors`: it imports nothing
else from dstoolkit, and every other layer may import it.

- :mod:`dstoolkit.utils.checks`: :func:`~dstoolkit.utils.checks.real_array`,
  :func:`~dstoolkit.utils.checks.real_number` and :func:`~dstoolkit.utils.checks.whole_number`
  turn bad input into an :class:`~dstoolkit.errors.InvalidInputError` that names the argument.
- :mod:`dstoolkit.utils.budget`: the memory budget (:func:`~dstoolkit.utils.budget.memory_budget`,
  :func:`~dstoolkit.utils.budget.set_memory_budget`) and the checks that refuse work over it
  before it starts (:func:`~dstoolkit.utils.budget.check_memory`,
  :func:`~dstoolkit.utils.budget.rows_per_chunk`).
- :mod:`dstoolkit.utils.outputs`: output files that lose nothing
  (:func:`~dstoolkit.utils.outputs.check_outputs`, :func:`~dstoolkit.utils.outputs.atomic_write`).
- :mod:`dstoolkit.utils.signals`: stop signals turned into exceptions, held while outputs
  are moved into place (:func:`~dstoolkit.utils.signals.stop_on_signals`).
- :mod:`dstoolkit.utils.console`: a command's standard output that prints on any locale and
  outlives a closed pipe (:func:`~dstoolkit.utils.console.command_console`).
"""
