"""A Sphinx directive that documents a click command tree: the CLI reference is generated from the code.

``.. click-tree:: module:attribute`` imports the click command (typer's ``typer.main.get_command(app)``) and writes
one section per command, nested as the command groups are: its help text, its usage line and a list of its
arguments and options, each with the same text ``--help`` prints. Typer ships its own copy of click, which
sphinx-click does not recognise; walking the tree here takes only the duck-typed parts both copies share
(``params``, ``get_help_record``, ``list_commands``, ``get_command``, ``get_usage``).
"""

from __future__ import annotations

import importlib
from typing import Any

from docutils import nodes
from docutils.parsers.rst import directives
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective


def _load(target: str) -> Any:
    module_name, _, attribute = target.partition(":")
    if not attribute:
        raise ValueError(f"click-tree expects module:attribute, got {target!r}")
    return getattr(importlib.import_module(module_name), attribute)


def _context(command: Any, name: str, parent: Any = None) -> Any:
    # the Context class of the click copy the command was built with (typer's or click's)
    context_class = getattr(command, "context_class", None)
    if context_class is None:
        context_class = type(parent) if parent is not None else importlib.import_module(
            type(command).__module__.rsplit(".", 1)[0] + ".core").Context
    return context_class(command, info_name=name, parent=parent)


def _paragraphs(text: str) -> list[nodes.Node]:
    return [nodes.paragraph(text=block.strip()) for block in text.split("\n\n") if block.strip()]


class ClickTree(SphinxDirective):
    """Document a click command and, recursively, its subcommands."""

    required_arguments = 1
    option_spec = {"prog": directives.unchanged_required}

    def run(self) -> list[nodes.Node]:
        command = _load(self.arguments[0])
        prog = self.options.get("prog", getattr(command, "name", None) or "cli")
        return self._document(command, prog, None, top=True)

    def _document(self, command: Any, path: str, parent_ctx: Any, *, top: bool = False) -> list[nodes.Node]:
        name = path.rsplit(" ", 1)[-1]
        ctx = _context(command, name, parent_ctx)
        section_id = nodes.make_id("cli " + path)
        section = nodes.section("", ids=[section_id], names=[nodes.fully_normalize_name(path)])
        section += nodes.title(text=path)
        self.state.document.note_implicit_target(section, section)
        section += _paragraphs(command.help or "")
        usage = command.get_usage(ctx).removeprefix("Usage: ")
        section += nodes.literal_block(usage, usage, language="none")
        records = [(param, param.get_help_record(ctx)) for param in command.params]
        records = [(param, record) for param, record in records if record is not None]
        if records:
            items = nodes.definition_list()
            for _param, (opts, help_text) in records:
                item = nodes.definition_list_item()
                term = nodes.term()
                term += nodes.literal(text=opts)
                item += term
                definition = nodes.definition()
                definition += _paragraphs(help_text or " ") or [nodes.paragraph(text="")]
                item += definition
                items += item
            rubric = "Arguments and options" if not top else "Options of every command (given before the command name)"
            section += nodes.rubric(text=rubric)
            section += items
        if hasattr(command, "list_commands"):
            for sub_name in command.list_commands(ctx):
                sub = command.get_command(ctx, sub_name)
                if sub is None or getattr(sub, "hidden", False):
                    continue
                section += self._document(sub, f"{path} {sub_name}", ctx)
        return [section]


def setup(app: Sphinx) -> dict[str, Any]:
    app.add_directive("click-tree", ClickTree)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
