"""The benchmark's tables (rich; Markdown for BENCHMARKS.md) from the result dict of bench.suite."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from rich import box
from rich.console import Console
from rich.table import Table

ENGINE_TITLES = {"rustycs": "rustycs", "pymunk": "pymunk", "pyb2d3": "Box2D v3 (pyb2d3)"}
QUALITY_TITLES = {
    "top_displacement": "top box displacement, m",
    "max_displacement": "worst box displacement, m",
    "max_overlap": "deepest overlap, m",
    "escaped": "escaped bodies",
    "outside": "bodies outside the box",
    "mean_radius_drift": "mean relative drift of the orbit radius",
    "max_radius_drift": "max relative drift of the orbit radius",
}


def print_report(result: dict[str, Any], markdown: bool = False, console: Console | None = None) -> None:
    """Print every table of `result` (Markdown tables when `markdown`)."""
    if console is None:  # tables never wrap into an unreadable column when piped or as Markdown
        console = Console()
        if markdown or not console.is_terminal:
            console = Console(width=200)
    style = box.MARKDOWN if markdown else box.SIMPLE_HEAVY
    meta = result["meta"]
    console.print(f"{meta['cpu']}, {meta['cores']} cores; {meta['date']}; `{meta['command']}`",
                  highlight=False)
    for engine, settings in meta["settings"]["engines"].items():
        console.print(f"{'- ' if markdown else ''}{ENGINE_TITLES[engine]}: {settings}", highlight=False)
    for table in tables(result):
        table.box = style
        console.print()
        if markdown:  # a Markdown title line, not rich's centred (indented, so code-block) one
            console.print(f"**{table.title}**", highlight=False)
            console.print()
            table.title = None
        console.print(table)


def tables(result: dict[str, Any]) -> list[Table]:
    """The speed, quality, compile and scaling tables that `result` has data for."""
    reps = result["meta"]["reps"]
    ran = _settings_caption(result["meta"]["settings"])
    out = []
    if result.get("scenes"):
        title = f"ms per tick, median (min) of {reps} fresh processes; ratio = rustycs / peer; {ran}"
        out.append(_speed_table(result["scenes"], "scene", title))
        quality = _quality_table(result["scenes"], ran)
        if quality.row_count:
            out.append(quality)
    if "recording" in result:
        out.append(_recording_table(result["recording"]))
    if "compile" in result:
        out.append(_compile_table(result["compile"]))
    if result.get("scaling"):
        ticks = next(iter(result["scaling"].values())).get("ticks", "?")
        out.append(_speed_table(result["scaling"], "bodies",
                                f"scaling: circles in a container, ms per tick over {ticks} ticks; {ran}"))
        out.append(_memory_table(result["scaling"], ran))
    return out


def _settings_caption(settings: dict[str, Any]) -> str:
    """The run's options in a table's title, so that a table copied alone still says what ran."""
    threads = settings["threads"]
    return (f"sleeping {'on' if settings['sleep'] else 'off'}, "
            f"{threads} thread{'s' if threads > 1 else ''} per world")


def _engines(rows: dict[str, Any]) -> list[str]:
    seen: dict[str, None] = {}
    for row in rows.values():
        seen.update(dict.fromkeys(row["engines"]))
    return list(seen)


def _speed_table(rows: dict[str, Any], key_title: str, title: str) -> Table:
    engines = _engines(rows)
    table = Table(title=title)
    table.add_column(key_title)
    if key_title == "scene":
        table.add_column("bodies", justify="right")
    table.add_column("ticks", justify="right")
    for engine in engines:
        table.add_column(ENGINE_TITLES[engine], justify="right")
        if engine != "rustycs":
            table.add_column("ratio", justify="right")
    for key, row in rows.items():
        cells = [row.get("name", key)] if key_title == "scene" else [key]
        if key_title == "scene":
            cells.append(str(row.get("bodies", "?")))
        cells.append(str(row.get("ticks", "?")))
        for engine in engines:
            cell = row["engines"].get(engine, {})
            cells.append(_timing(cell))
            if engine != "rustycs":
                ratio = row["ratios"].get(engine)
                cells.append("–" if ratio is None else f"{ratio:.2f}")
        table.add_row(*cells)
    return table


def _memory_table(rows: dict[str, Any], ran: str) -> Table:
    """Resident memory per body after each scaling run, median of the repetitions."""
    engines = _engines(rows)
    table = Table(title="scaling: resident memory of the engine's world after the run, KB per body, "
                  f"median; {ran}")
    table.add_column("bodies")
    for engine in engines:
        table.add_column(ENGINE_TITLES[engine], justify="right")
    for key, row in rows.items():
        values = [row["engines"].get(engine, {}).get("median_kb_per_body") for engine in engines]
        table.add_row(key, *("–" if value is None else f"{value:.1f}" for value in values))
    return table


def _timing(cell: dict[str, Any]) -> str:
    if cell.get("median_ms") is None:
        return "failed" if cell.get("errors") else "–"
    return f"{_ms(cell['median_ms'])} ({_ms(cell['min_ms'])})"


def _ms(value: float) -> str:
    return f"{value:.4f}" if value < 0.1 else f"{value:.3f}" if value < 10 else f"{value:.1f}"


def _quality_table(rows: dict[str, Any], ran: str) -> Table:
    engines = _engines(rows)
    table = Table(title="quality at the end of each run (from the final poses, same measures for all); "
                  + ran)
    table.add_column("scene")
    table.add_column("measure")
    for engine in engines:
        table.add_column(ENGINE_TITLES[engine], justify="right")
    for key, row in rows.items():
        names = next((c["quality"] for c in row["engines"].values() if "quality" in c), {})
        for name in names:
            values = [row["engines"].get(e, {}).get("quality", {}).get(name) for e in engines]
            table.add_row(row.get("name", key), QUALITY_TITLES.get(name, name), *map(_quantity, values))
    return table


def _quantity(value: float | int | None) -> str:
    if value is None:
        return "–"
    return str(value) if isinstance(value, int) else f"{value:.3g}"


def _recording_table(recording: dict[str, Any]) -> Table:
    table = Table(title="recording: rustycs run writing every tick to HDF5, against stepping only")
    for title in ("scene", "ticks", "stepping only, ms/tick", "run with recording, ms/tick", "overhead",
                  "peak memory, MB"):
        table.add_column(title, justify="left" if title == "scene" else "right")

    def number(key: str, fmt: Callable[[float], str]) -> str:
        value = recording.get(key)
        return "–" if value is None else fmt(value)

    table.add_row(str(recording.get("name")), str(recording.get("ticks")), number("stepping_median_ms", _ms),
                  number("median_ms", _ms), number("overhead", lambda v: f"{100 * v:+.0f} %"),
                  number("peak_memory_mb", lambda v: f"{v:.0f}"))
    return table


def _compile_table(times: dict[str, Any]) -> Table:
    table = Table(title="compile and start-up, seconds (wall time, fresh processes)")
    table.add_column("what")
    table.add_column("s", justify="right")
    for label, key in (("cold compile: first step with an empty kernel cache", "cold_s"),
                       ("warm start: first step with the cached kernels", "warm_s"),
                       ("import rustycs", "import_s"),
                       ("start-up: rustycs --help", "startup_s")):
        value = times.get(key)
        table.add_row(label, "failed" if value is None else f"{value:.2f}")
    return table
