"""The wheel's packages: pyproject.toml holds everything else. One package per generated folder
is found here, so that a new mechanism's package ships with no edit to any configuration (a
static list in pyproject.toml would leave it out, and setuptools warns about every folder of
Python files it was not told about)."""

from pathlib import Path

from setuptools import setup

GENERATED = Path(__file__).parent / "generated"
FOLDERS = sorted(p.name for p in GENERATED.iterdir() if (p / "manifest.json").is_file())

setup(
    packages=[
        "parakin",
        "parakin.packages",
        "parakin.solvers",
        "parakin.studies",
        "parakin.interfaces",
        "parakin.calibration",
        "parakin.generator",
        "parakin.generator.templates",
        "parakin.generator.runtime",
        "parakin.mechanisms",
        "parakin.generated",
        *(f"parakin.generated.{name}" for name in FOLDERS),
    ],
    package_data={
        "parakin": ["py.typed"],
        "parakin.interfaces": ["viewer.html"],
        "parakin.generator.templates": ["*.j2", "*.h"],
        "parakin.generator.runtime": ["*.c", "*.h"],
        **{f"parakin.generated.{name}": ["*.json", "*.c", "*.h", "*.md"] for name in FOLDERS},
    },
)
