"""Mechanism definitions: one module per mechanism, each exposing ``build() -> Mechanism``."""

MECHANISMS = ["sam", "spm", "sps", "gough"]
