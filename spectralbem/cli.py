"""Command line: ``spectralbem info | demo | plot``.

Examples::

    spectralbem info
    spectralbem demo --out demo_out
    spectralbem plot demo_out/demo.nc -o contact.png
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def _info(args) -> int:
    import platform

    import numpy
    import scipy

    from . import __version__, fft

    print(f"spectralbem {__version__}")
    print(f"python {platform.python_version()}, numpy {numpy.__version__}, "
          f"scipy {scipy.__version__}")
    print(f"FFT backend: {fft.backend()}, threads: {fft.get_threads()}")
    return 0


def _demo(args) -> int:
    from .demo import run

    run(Path(args.out))
    return 0


def _plot(args) -> int:
    from .io import read_dataset
    from .plotting import plot_contact

    path = Path(args.dataset)
    if not path.is_file():
        raise FileNotFoundError(f"dataset {str(path)!r} does not exist")
    ds = read_dataset(path)
    out = Path(args.output) if args.output else path.with_suffix(".png")
    plot_contact(ds, out)
    print(f"wrote {out}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="spectralbem", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("info", help="versions, FFT backend and threads",
                       description="Print versions, the FFT backend and thread count.\n\n"
                                   "example: spectralbem info")
    p.set_defaults(func=_info)
    p = sub.add_parser("demo", help="run the default scene",
                       description="Run the default scene and write demo.nc and demo.png.\n\n"
                                   "example: spectralbem demo --out demo_out")
    p.add_argument("--out", default="demo_out", help="output folder (default demo_out)")
    p.set_defaults(func=_demo)
    p = sub.add_parser("plot", help="plot a result dataset",
                       description="Plot the contact map, pressure and a profile cut of a "
                                   "result dataset.\n\nexample: spectralbem plot out.nc -o out.png")
    p.add_argument("dataset", help="netCDF result file")
    p.add_argument("-o", "--output", help="PNG path (default: dataset name with .png)")
    p.set_defaults(func=_plot)
    return ap


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except Exception as exc:  # one-line reason, non-zero exit
        print(f"spectralbem {args.command}: error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
