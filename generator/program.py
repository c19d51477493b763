"""Straight-line programs: named inputs, ordered assignments, named outputs, with CSE.

A ``Program`` is the unit every emitter renders: one generated function. Inputs are groups of
symbols that arrive as arrays whose last axis indexes the group (so a leading batch shape
broadcasts through); outputs are SymPy matrices (a column vector is emitted as a 1-D output).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp


@dataclass(frozen=True)
class Assignment:
    target: sp.Symbol
    value: sp.Expr


@dataclass(frozen=True)
class OutputEntry:
    index: tuple[int, ...]
    value: sp.Expr


@dataclass(frozen=True)
class Output:
    name: str
    shape: tuple[int, ...]
    entries: list[OutputEntry]


@dataclass
class Program:
    """One generated function: ``name(*inputs) -> outputs`` (see module docstring)."""

    name: str
    doc: str
    inputs: list[tuple[str, list[sp.Symbol]]]
    outputs: list[tuple[str, sp.Matrix]]
    steps: list[tuple[sp.Symbol, sp.Expr]] = field(default_factory=list)

    def output_shape(self, matrix: sp.Matrix) -> tuple[int, ...]:
        return (matrix.rows,) if matrix.cols == 1 else (matrix.rows, matrix.cols)

    def lower(self) -> LoweredProgram:
        """Common-subexpression elimination: each step, then all outputs, in one pass each."""
        counter = 0
        body: list[Assignment] = []

        def eliminate(expressions: list[sp.Expr]) -> list[sp.Expr]:
            nonlocal counter
            names = sp.numbered_symbols("_t", start=counter)
            replacements, reduced = sp.cse(expressions, symbols=names, order="canonical")
            for symbol, value in replacements:
                body.append(Assignment(symbol, value))
            counter += len(replacements)
            return list(reduced)

        for target, value in self.steps:
            (reduced,) = eliminate([value])
            body.append(Assignment(target, reduced))

        flat = [entry for _, matrix in self.outputs for entry in matrix]
        reduced_flat = iter(eliminate(flat))
        outputs = []
        for name, matrix in self.outputs:
            shape = self.output_shape(matrix)
            entries = []
            for row in range(matrix.rows):
                for col in range(matrix.cols):
                    index = (row,) if len(shape) == 1 else (row, col)
                    entries.append(OutputEntry(index, next(reduced_flat)))
            outputs.append(Output(name, shape, entries))
        operations = sum(sp.count_ops(a.value) for a in body) + sum(
            sp.count_ops(e.value) for o in outputs for e in o.entries
        )
        return LoweredProgram(self, body, outputs, int(operations))


@dataclass
class LoweredProgram:
    source: Program
    body: list[Assignment]
    outputs: list[Output]
    operations: int

    @property
    def name(self) -> str:
        return self.source.name

    def used_inputs(self) -> list[tuple[str, int, sp.Symbol]]:
        """(group, position, symbol) for every input symbol the program reads."""
        used: set[sp.Symbol] = set()
        for assignment in self.body:
            used |= assignment.value.free_symbols
        for output in self.outputs:
            for entry in output.entries:
                used |= entry.value.free_symbols
        return [
            (group, position, symbol)
            for group, symbols in self.source.inputs
            for position, symbol in enumerate(symbols)
            if symbol in used
        ]
