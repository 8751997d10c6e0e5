"""Argument types shared by the sub-commands (argparse turns their errors into one line)."""

from __future__ import annotations

import argparse


def years(text: str) -> float:
    """An age in years."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"age {text!r}: allowed a number of years, 18–90") from None


def unit_fraction(text: str) -> float:
    """A number 0..1 (checked by the library, which names the parameter)."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: allowed a number 0..1") from None


def add_body_arguments(parser: argparse.ArgumentParser) -> None:
    """--sex --age --stature --mass --muscle-tone --proportions, as a person writes them."""
    parser.add_argument("--sex", default="female", help="female, male, or 0 (female) … 1 (male); default female")
    parser.add_argument("--age", type=years, default=30.0, help="years, 18–90; default 30")
    parser.add_argument("--stature", default=None,
                        help="e.g. 165cm, 1.65m; default the default body's: female 165cm, male 178cm")
    parser.add_argument("--mass", default=None, help="e.g. 58kg; default the default body's: female 62kg, male 78kg")
    parser.add_argument("--muscle-tone", type=unit_fraction, default=None,
                        help="0..1, 0.5 = average; default: follows the mass (MakeHuman's build path)")
    parser.add_argument("--proportions", type=unit_fraction, default=0.5, help="0..1, 0.5 = average")
