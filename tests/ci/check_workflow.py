#!/usr/bin/env python3
"""Checks .github/workflows/ci.yml, which this workplace's CI never runs: it parses, its CPU job runs
.ci/run, and its GPU job runs on a self-hosted `gpu` runner, calls tools/device_run.sh and uploads the
files that script writes (summary and benchmark records) as artifacts.

    check_workflow.py SOURCE_DIR
"""
import pathlib
import re
import sys

import yaml


def fail(message):
    print(f"check_workflow: {message}", file=sys.stderr)
    sys.exit(1)


def run_lines(job):
    return "\n".join(step.get("run", "") for step in job.get("steps", []))


def main():
    root = pathlib.Path(sys.argv[1])
    path = root / ".github/workflows/ci.yml"
    workflow = yaml.safe_load(path.read_text())
    jobs = workflow.get("jobs") or fail(f"{path}: no jobs")
    for name in ("cpu", "gpu"):
        if name not in jobs:
            fail(f"{path}: no job '{name}' (jobs: {', '.join(jobs)})")

    cpu, gpu = jobs["cpu"], jobs["gpu"]
    if ".ci/run" not in run_lines(cpu):
        fail(f"{path}: job cpu does not run .ci/run")
    labels = gpu.get("runs-on")
    labels = [labels] if isinstance(labels, str) else list(labels or [])
    if "self-hosted" not in labels or "gpu" not in labels:
        fail(f"{path}: job gpu runs on {labels}, expected a self-hosted runner labelled gpu")
    if "tools/device_run.sh" not in run_lines(gpu):
        fail(f"{path}: job gpu does not call tools/device_run.sh")
    if not (root / "tools/device_run.sh").is_file():
        fail("tools/device_run.sh is missing")

    # The artifacts are the files device_run.sh leaves in $OUT, as its header lists them.
    script = (root / "tools/device_run.sh").read_text()
    written = set(re.findall(r'"\$out/([\w.-]+)"', script))
    uploads = [step for step in gpu["steps"] if str(step.get("uses", "")).startswith("actions/upload-artifact")]
    if not uploads:
        fail(f"{path}: job gpu uploads no artifact")
    uploaded = set(re.findall(r"romp-device/([\w.-]+)", uploads[0].get("with", {}).get("path", "")))
    if uploads[0].get("if") != "always()":
        fail(f"{path}: job gpu uploads its artifacts only when every step passed (want if: always())")
    if not written or written != uploaded:
        fail(f"{path}: job gpu uploads {sorted(uploaded)} but tools/device_run.sh writes {sorted(written)}")
    if len(written) > 8:
        fail(f"tools/device_run.sh writes {len(written)} files to $OUT; a lent machine returns at most 8")
    print(f"check_workflow: jobs {', '.join(jobs)}; gpu uploads {', '.join(sorted(uploaded))}")


if __name__ == "__main__":
    main()
