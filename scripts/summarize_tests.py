#!/usr/bin/env python3
"""Summarise JUnit-style XML test results (gtest, rostest, fuzz smoke).

usage: summarize_tests.py DIR [DIR...]
Prints failed and skipped tests (with reasons), then the closing line
"N passed, N failed, N skipped". Exit status 1 when anything failed or when
no test ran at all.
"""
import glob
import os
import sys
import xml.etree.ElementTree as ET


def cases(path):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as err:
        yield (os.path.basename(path), "failed", f"unreadable result file: {err}")
        return
    for case in root.iter("testcase"):
        name = f"{case.get('classname', '')}.{case.get('name', '')}".strip(".")
        failure = case.find("failure")
        if failure is None:
            failure = case.find("error")
        skipped = case.find("skipped")
        if failure is not None:
            text = (failure.get("message") or failure.text or "").strip()
            yield (name, "failed", text.splitlines()[0] if text else "")
        elif skipped is not None or case.get("result") == "skipped" or case.get("status") == "notrun":
            reason = (skipped.get("message") if skipped is not None else "") or ""
            yield (name, "skipped", reason.strip())
        else:
            yield (name, "passed", "")


def main(dirs):
    counts = {"passed": 0, "failed": 0, "skipped": 0}
    failed, skipped = [], []
    for d in dirs:
        for path in sorted(glob.glob(os.path.join(d, "**", "*.xml"), recursive=True)):
            for name, status, text in cases(path):
                counts[status] += 1
                if status == "failed":
                    failed.append((name, text))
                elif status == "skipped":
                    skipped.append((name, text))
    for name, text in skipped:
        print(f"SKIPPED {name}: {text}")
    for name, text in failed:
        print(f"FAILED  {name}: {text}")
    if counts["skipped"]:
        print(f"{counts['skipped']} test(s) skipped")
    print(f"{counts['passed']} passed, {counts['failed']} failed, {counts['skipped']} skipped")
    total = sum(counts.values())
    return 1 if counts["failed"] or total == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
