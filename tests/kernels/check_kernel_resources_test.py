#!/usr/bin/env python3
"""The kernel resource check itself: it reads ptxas's report, and fails on every kind of excess and on a
budget that checks nothing, so that build.kernel_resources cannot pass by reading nothing."""
import pathlib
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).parent))
import check_kernel_resources as checker  # noqa: E402

# Two kernels as ptxas --resource-usage prints them, each for sm_80 and sm_90 (with other info lines).
REPORT = """\
ptxas info    : 0 bytes gmem
ptxas info    : Compiling entry function '_Z3hotPf' for 'sm_80'
ptxas info    : Function properties for _Z3hotPf
    16 bytes stack frame, 8 bytes spill stores, 8 bytes spill loads
ptxas info    : Used 200 registers, used 0 barriers, 384 bytes cmem[0]
ptxas info    : Compiling entry function '_Z3hotPf' for 'sm_90'
ptxas info    : Function properties for _Z3hotPf
    24 bytes stack frame, 20 bytes spill stores, 56 bytes spill loads
ptxas info    : Used 255 registers, used 0 barriers
ptxas info    : Compile time = 1.5 ms
ptxas info    : Compiling entry function '_Z4coldPi' for 'sm_90'
ptxas info    : Function properties for _Z4coldPi
    0 bytes stack frame, 0 bytes spill stores, 0 bytes spill loads
ptxas info    : Used 12 registers, used 0 barriers
"""


class ParseAndCheck(unittest.TestCase):
    def test_reads_the_chosen_architecture_only(self):
        kernels = checker.parse_report(REPORT, "sm_90")
        self.assertEqual(kernels["_Z3hotPf"], {"registers": 255, "stack": 24, "spills": 76})
        self.assertEqual(kernels["_Z4coldPi"], {"registers": 12, "stack": 0, "spills": 0})
        self.assertEqual(checker.parse_report(REPORT, "sm_80")["_Z3hotPf"]["stack"], 16)

    def test_demangles(self):
        self.assertEqual(checker.demangle(["_Z3hotPf"]), {"_Z3hotPf": "hot(float*)"})

    def test_each_excess_fails_and_a_budget_met_passes(self):
        kernels = {"hot(float*)": {"registers": 255, "stack": 24, "spills": 76}}
        for key in ("registers", "stack", "spills"):
            budget = {"match": "hot(", "file": "b.toml", key: kernels["hot(float*)"][key] - 1}
            failures = checker.check(kernels, [budget])
            self.assertEqual(len(failures), 1, key)
            self.assertIn(key, failures[0])
        met = {"match": "hot(", "file": "b.toml", "registers": 255, "stack": 24, "spills": 76}
        self.assertEqual(checker.check(kernels, [met]), [])

    def test_a_budget_that_matches_no_kernel_fails(self):
        failures = checker.check({"hot(float*)": {"registers": 1, "stack": 0, "spills": 0}},
                                 [{"match": "renamed", "file": "b.toml", "stack": 0}])
        self.assertEqual(len(failures), 1)
        self.assertIn("matches no kernel", failures[0])

    def test_the_command_fails_on_excess_and_on_an_empty_build(self):
        script = pathlib.Path(checker.__file__)
        with tempfile.TemporaryDirectory() as folder:
            root = pathlib.Path(folder)
            (root / "build").mkdir()
            budget = root / "budget.toml"
            budget.write_text('[[kernel]]\nmatch = "hot("\nstack = 0\nspills = 0\n')
            run = lambda: subprocess.run([sys.executable, script, root / "build", budget, root / "table.txt"],
                                         capture_output=True, text=True)
            self.assertEqual(run().returncode, 1)  # no report at all
            (root / "build" / "k.cu.o.resources").write_text(REPORT)
            result = run()
            self.assertEqual(result.returncode, 1)
            self.assertIn("stack 24 > budget 0", result.stderr)
            self.assertIn("hot(float*)", (root / "table.txt").read_text())
            budget.write_text('[[kernel]]\nmatch = "hot("\nstack = 24\nspills = 76\n')
            self.assertEqual(run().returncode, 0)


# Two functions as cuobjdump -sass lists them: a copy that waits for each load before its store, and one that
# issues three loads before its first store.
SASS = """\
\tcode for sm_90
\t\tFunction : _Z3hotPf
\t.headerflags\t@"EF_CUDA_SM90 EF_CUDA_VIRTUAL_SM(EF_CUDA_SM90)"
        /*0110*/              @!P1 LDG.E R9, desc[UR4][R2.64] ;
        /*01e0*/              @!P1 STG.E desc[UR4][R4.64], R9 ;
        /*01f0*/              @!P0 LDG.E R11, desc[UR4][R6.64] ;
        /*02c0*/              @!P0 STG.E desc[UR4][R2.64], R11 ;
        /*0350*/                   EXIT ;
\t\t..........
\t\tFunction : _Z4coldPi
        /*0210*/                   LDG.E.CONSTANT R3, desc[UR4][R2.64] ;
        /*0250*/                   LDG.E.CONSTANT R7, desc[UR4][R6.64] ;
        /*0260*/                   IMAD R1, R2, R3, RZ ;
        /*0270*/                   LDG.E.CONSTANT R5, desc[UR4][R4.64] ;
        /*0320*/                   STG.E desc[UR4][R14.64], R3 ;
        /*0330*/                   LDG.E.CONSTANT R3, desc[UR4][R2.64] ;
        /*0338*/                   LDG.E.CONSTANT R8, desc[UR4][R2.64] ;
        /*0340*/                   RED.E.ADD.F32.FTZ.RN.STRONG.GPU desc[UR4][R16.64], R7 ;
        /*0350*/                   LDG.E R3, desc[UR4][R2.64] ;
        /*0358*/                   LDG.E R9, desc[UR4][R2.64] ;
        /*0400*/                   EXIT ;
"""


class LoadsInFlight(unittest.TestCase):
    def test_counts_the_longest_run_of_loads_between_stores_and_atomics(self):
        functions = checker.sass_functions(SASS)
        self.assertEqual(sorted(functions), ["_Z3hotPf", "_Z4coldPi"])
        self.assertEqual(checker.loads_in_flight(functions["_Z3hotPf"]), 1)
        self.assertEqual(checker.loads_in_flight(functions["_Z4coldPi"]), 3)

    def test_fewer_than_the_budget_fails(self):
        kernels = {"hot(float*)": {"registers": 1, "stack": 0, "spills": 0, "loads_in_flight": 1}}
        failures = checker.check(kernels, [{"match": "hot(", "file": "b.toml", "loads_in_flight": 4}])
        self.assertEqual(len(failures), 1)
        self.assertIn("loads_in_flight 1 < budget 4", failures[0])
        kernels["hot(float*)"]["loads_in_flight"] = 4
        self.assertEqual(checker.check(kernels, [{"match": "hot(", "file": "b.toml", "loads_in_flight": 4}]), [])

    def test_a_loads_budget_without_cuobjdump_fails(self):
        script = pathlib.Path(checker.__file__)
        with tempfile.TemporaryDirectory() as folder:
            root = pathlib.Path(folder)
            (root / "build").mkdir()
            (root / "build" / "k.cu.o.resources").write_text(REPORT)
            budget = root / "budget.toml"
            budget.write_text('[[kernel]]\nmatch = "cold("\nloads_in_flight = 2\n')
            result = subprocess.run([sys.executable, script, root / "build", budget, root / "table.txt"],
                                    capture_output=True, text=True)
            self.assertEqual(result.returncode, 1)
            self.assertIn("--cuobjdump", result.stderr)


if __name__ == "__main__":
    unittest.main()
