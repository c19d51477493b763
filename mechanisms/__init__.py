"""Mechanism definitions: one module per mechanism, each exposing ``build() -> Mechanism``."""

MECHANISMS = ["sam", "spm", "sphere2r", "sps", "gough"]
