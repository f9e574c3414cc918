"""The Flamenco job type's STEPS block (farm/flamenco/turkish_lipsync.js) made again from farm/steps.toml,
as core/farm/jobs.py renders it; run after changing the steps, before a release.

    python -m tools.release.flamenco           # write the job type's STEPS block
    python -m tools.release.flamenco --check   # exit 1 when the job type's block is not steps.toml's
"""

from __future__ import annotations

import argparse
import sys

from turkish_lipsync.core.farm.jobs import FLAMENCO_JOB_TYPE, flamenco_block, job_type_block

COMMAND = "python -m tools.release.flamenco"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="exit 1 when the block is not current")
    arguments = parser.parse_args(argv)
    text = FLAMENCO_JOB_TYPE.read_text(encoding="utf-8")
    current, wanted = job_type_block(text), flamenco_block()
    if arguments.check:
        if current != wanted:
            print(f"{FLAMENCO_JOB_TYPE}: its STEPS block is not farm/steps.toml's; run {COMMAND}")
            return 1
        return 0
    FLAMENCO_JOB_TYPE.write_text(text.replace(current, wanted), encoding="utf-8")
    print(f"Wrote the STEPS block of {FLAMENCO_JOB_TYPE}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
