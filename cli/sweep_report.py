"""What `rustycs sweep` shows: a progress bar over variants, the table of rows, and the failures."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .sweep import SweepResult, Variant, VariantOutcome

# summary statistics shown in the table (all of them are in sweep.csv): key -> column header
TABLE_STATISTICS = {
    "ticks": "ticks", "final_kinetic_energy": "final KE (J)", "max_penetration": "max pen. (m)"
}


@contextmanager
def variant_progress(
    enabled: bool, total: int, label: str
) -> Iterator[Callable[[Variant, VariantOutcome], None]]:
    """A transient progress bar over variants on stderr, only on a terminal; yields the per-outcome
    callback (a no-op when there is no bar)."""
    if not (enabled and sys.stderr.isatty()):
        yield lambda _variant, _outcome: None
        return
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TextColumn("variants"),
               TextColumn("{task.fields[failed]}"), TimeElapsedColumn())
    failed = 0
    with Progress(*columns, console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(label, total=total, failed="")

        def advance(_variant: Variant, outcome: VariantOutcome) -> None:
            nonlocal failed
            failed += outcome.failed
            bar.update(task, advance=1, failed=f"[red]{failed} failed[/]" if failed else "")

        yield advance


def print_sweep_table(result: SweepResult) -> None:
    """One line per variant on stdout: its swept values, status and a few statistics."""
    from rich.console import Console
    from rich.table import Table

    rows = result.rows()
    keys = [swept.key for swept in result.plan.swept]
    measures = list(dict.fromkeys(key for row in rows for key in row if key.startswith("measure.")))
    table = Table(title=f"sweep of {result.plan.scene_name}: {len(rows)} variants", title_justify="left")
    for column in ("#", *keys, "status", *TABLE_STATISTICS.values(), *measures):
        table.add_column(column, justify="left" if column == "status" else "right")
    for row in rows:
        status = row["status"] + (" (done before)" if row["skipped"] else "")
        style = "red" if row["status"] in ("failed", "diverged") else None
        cells = [_cell(row.get(column)) for column in ("index", *keys)]
        statistics = [_cell(row.get(column)) for column in (*TABLE_STATISTICS, *measures)]
        table.add_row(*cells, status, *statistics, style=style)
    console = Console(highlight=False)
    console.print(table)
    console.print(f"trajectories and tables (sweep.csv, sweep.json) in {result.plan.out_dir}")


def _cell(value: object) -> str:
    if value is None:
        return ""
    return f"{value:.4g}" if isinstance(value, float) else str(value)


def report_problems(result: SweepResult) -> None:
    """Name every failed variant on stderr, and say how to resume an interrupted sweep."""
    for variant, outcome in result.failures():
        print(f"rustycs: variant {variant.task.index} ({variant.label}) {outcome.status}: {outcome.error}",
              file=sys.stderr)
    if result.interrupted:
        print("rustycs: sweep interrupted; run the same command again to resume it", file=sys.stderr)
