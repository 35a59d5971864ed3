#!/usr/bin/env python3
"""How often each method disagreed with the exact reference, per scene family.

Runs `hedra compare SCENE --json` on every scenes/**/*.json (or reads saved
documents with --from DIR) and prints a Markdown table: one row per family
(the directory under scenes/; top-level files are family "."), one column per
method (hedra, then the peers), each cell "D/N" = disagreed / answered
(agree + disagree + partial; partial = the boolean only, which agreed), then
"f" for failed calls (error, crash, timeout) and "u" for queries the method
cannot pose (unsupported), when there are any. Python 3 standard library only.

  python3 tools/cli/compare/compare_summary.py --hedra build/bin/hedra --scenes scenes
"""
import argparse
import collections
import json
import os
import subprocess
import sys


def scene_files(root):
    for directory, _, names in os.walk(root):
        for name in sorted(names):
            if name.endswith(".json"):
                yield os.path.join(directory, name)


def family_of(path, root):
    relative = os.path.relpath(path, root)
    head = os.path.dirname(relative)
    return head.split(os.sep)[0] if head else "."


def run_compare(hedra, path, extra):
    done = subprocess.run([hedra, "compare", path, "--json"] + extra, capture_output=True, text=True)
    if done.returncode not in (0, 1):
        sys.exit("%s compare %s: exit %d\n%s" % (hedra, path, done.returncode, done.stderr))
    return json.loads(done.stdout)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--hedra", default="build/bin/hedra", help="the hedra executable")
    parser.add_argument("--scenes", default="scenes", help="the scene directory")
    parser.add_argument("--peer-timeout", help="passed to hedra compare")
    args = parser.parse_args()

    extra = ["--peer-timeout", args.peer_timeout] if args.peer_timeout else []
    # counts[family][method][verdict]
    counts = collections.defaultdict(lambda: collections.defaultdict(collections.Counter))
    queries = collections.Counter()
    scenes = collections.Counter()
    methods = []
    hedra_disagreements = []
    for path in sorted(scene_files(args.scenes)):
        family = family_of(path, args.scenes)
        document = run_compare(args.hedra, path, extra)
        scenes[family] += 1
        for query in document["queries"]:
            queries[family] += 1
            for answer in [query["hedra"]] + query["peers"]:
                if answer["method"] not in methods:
                    methods.append(answer["method"])
                counts[family][answer["method"]][answer["verdict"]] += 1
            # A continuous query whose first-contact trace ran out is not judged.
            unavailable = query["hedra"]["verdict"] == "no_reference" and "first_contact" in query["reference"]
            if query["hedra"]["verdict"] != "agree" and not unavailable:
                hedra_disagreements.append("%s [%d] %s-%s %s: %s" % (
                    path, query["index"], query["a"], query["b"], query["type"], query["hedra"]["detail"]))

    def cell(c):
        answered = c["agree"] + c["disagree"] + c["partial"]
        text = "%d/%d" % (c["disagree"], answered)
        if c["failed"]:
            text += " %df" % c["failed"]
        if c["unsupported"]:
            text += " %du" % c["unsupported"]
        if c["no_reference"]:
            text += " %d no ref" % c["no_reference"]
        return text

    families = sorted(queries)
    print("| family (scenes, queries) | " + " | ".join(methods) + " |")
    print("|---|" + "---|" * len(methods))
    total = collections.defaultdict(collections.Counter)
    for family in families:
        row = ["%s (%d, %d)" % (family, scenes[family], queries[family])]
        for method in methods:
            row.append(cell(counts[family][method]))
            total[method].update(counts[family][method])
        print("| " + " | ".join(row) + " |")
    print("| **all (%d, %d)** | " % (sum(scenes.values()), sum(queries.values())) +
          " | ".join(cell(total[m]) for m in methods) + " |")
    if hedra_disagreements:
        print("\nhedra disagrees with the exact reference on:")
        for line in hedra_disagreements:
            print("- " + line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
