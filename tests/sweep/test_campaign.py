"""plcsweep's campaign file and its expansion (docs/campaigns.md): every
parameter form, faults, overrides by path with located errors, the stable
scenario hash. No plcrun needed."""

import atexit
import os
import shutil
import tempfile
import textwrap
import unittest

from plcsweep import campaign as C
from plcsweep import iec_time
from plcsweep.yaml_nodes import CampaignError

BASE = textwrap.dedent("""\
    cell: t
    libraries: [lib/libcell.so]
    tasks:
      - name: main
        period: 1ms
        programs: [P]
    programs:
      - name: P
        type: Demo
    plugins:
      - name: sim
    devices:
      - name: dev
        plugin: sim
        model: first_order
        input: "%IW0"
        output: "%QW0"
        params: {tau: 2s, gain: 1.5}
    retain:
      file: cell.retain
    hmi:
      prefix: T
    """)

CHECKS = textwrap.dedent("""\
    checks:
      - name: c
        always: "P.x = 0"
    """)


class Dir:
    def __init__(self):
        self.path = tempfile.mkdtemp(prefix="plcsweep-test-")
        atexit.register(shutil.rmtree, self.path, True)
        with open(os.path.join(self.path, "cell.yaml"), "w") as f:
            f.write(BASE)

    def campaign(self, body, checks=CHECKS):
        p = os.path.join(self.path, "c.yaml")
        with open(p, "w") as f:
            f.write("base: cell.yaml\nduration: 10s\n" + textwrap.dedent(body) + checks)
        return p


def load(body, checks=CHECKS):
    d = Dir()
    c = C.load(d.campaign(body, checks))
    return d, c


class ParameterForms(unittest.TestCase):
    def test_list_and_range_with_steps_make_a_full_grid(self):
        d, c = load("""\
            parameters:
              - path: devices.dev.params.gain
                values: [1, 2, 3]
              - path: tasks.main.period
                range: {from: 1ms, to: 3ms, steps: 3}
            """)
        s = C.expand(c)
        self.assertEqual(len(s), 9)
        self.assertEqual([x.params["devices.dev.params.gain"] for x in s[:3]], [1, 1, 1])
        self.assertEqual([x.params["tasks.main.period"] for x in s[:3]], ["1ms", "2ms", "3ms"])
        self.assertEqual(s[8].params, {"devices.dev.params.gain": 3, "tasks.main.period": "3ms"})
        self.assertIn("period: 3ms", s[8].config_text)
        self.assertIn("gain: 3", s[8].config_text)
        self.assertEqual(len({x.hash for x in s}), 9)

    def test_numeric_range_steps_are_even_and_integer_rounds(self):
        d, c = load("""\
            parameters:
              - path: devices.dev.params.gain
                range: {from: 0.0, to: 1.0, steps: 5}
              - path: programs.P.init.n
                range: {from: 0, to: 10, steps: 3}
                integer: true
            """)
        s = C.expand(c)
        self.assertEqual(sorted({x.params["devices.dev.params.gain"] for x in s}),
                         [0.0, 0.25, 0.5, 0.75, 1.0])
        self.assertEqual(sorted({x.params["programs.P.init.n"] for x in s}), [0, 5, 10])

    def test_random_is_reproducible_by_seed_and_stays_in_range(self):
        body = """\
            seed: %d
            sampling: random
            samples: 50
            parameters:
              - path: devices.dev.params.gain
                range: {from: 2.0, to: 3.0}
              - path: devices.dev.params.tau
                values: [1s, 2s]
            """
        _, a = load(body % 1)
        _, b = load(body % 1)
        _, other = load(body % 2)
        sa, sb, so = C.expand(a), C.expand(b), C.expand(other)
        self.assertEqual([x.hash for x in sa], [x.hash for x in sb])
        self.assertNotEqual([x.hash for x in sa], [x.hash for x in so])
        gains = [x.params["devices.dev.params.gain"] for x in sa]
        self.assertTrue(all(2.0 <= g <= 3.0 for g in gains))
        self.assertEqual({x.params["devices.dev.params.tau"] for x in sa}, {"1s", "2s"})

    def test_latin_hypercube_puts_one_sample_in_each_stratum(self):
        _, c = load("""\
            sampling: lhs
            samples: 40
            seed: 9
            parameters:
              - path: devices.dev.params.gain
                range: {from: 0.0, to: 40.0}
              - path: devices.dev.params.tau
                range: {from: 1s, to: 41s}
            """)
        s = C.expand(c)
        self.assertEqual(len(s), 40)
        gains = sorted(int(x.params["devices.dev.params.gain"]) for x in s)
        self.assertEqual(gains, list(range(40)))  # each 1-wide stratum once
        taus = sorted(iec_time.parse(x.params["devices.dev.params.tau"]) // 10**9 for x in s)
        self.assertEqual(taus, list(range(1, 41)))

    def test_lhs_without_samples_is_refused_at_the_sampling_line(self):
        d = Dir()
        with self.assertRaises(CampaignError) as e:
            C.load(d.campaign("sampling: lhs\n"))
        self.assertEqual((e.exception.line, e.exception.column), (3, 11))
        self.assertIn("needs 'samples: N'", str(e.exception))


class Faults(unittest.TestCase):
    def test_grid_runs_each_optional_fault_on_and_off(self):
        _, c = load("""\
            parameters:
              - path: devices.dev.params.gain
                values: [1, 2]
            faults:
              - name: cut
                device: dev
                probability: 0.5
                link_down_at: 3s
                link_down_for: 50ms
              - name: noisy
                device: dev
                params: {gain: {factor: 3}}
            """)
        s = C.expand(c)
        self.assertEqual(len(s), 4)
        self.assertEqual([sorted(x.faults) for x in s],
                         [["noisy"], ["cut", "noisy"], ["noisy"], ["cut", "noisy"]])
        # The factor scales the value this scenario has (the parameter's).
        self.assertEqual(s[2].faults["noisy"], {"gain": 6.0})
        self.assertIn("link_down_at: 3s", s[1].config_text)
        self.assertIn("link_down_for: 50ms", s[1].config_text)
        self.assertNotIn("link_down_at", s[0].config_text)

    def test_uniform_times_are_drawn_per_scenario_inside_the_window(self):
        _, c = load("""\
            sampling: random
            samples: 200
            faults:
              - name: cut
                device: dev
                probability: 0.3
                link_down_at: {uniform: [10s, 60s]}
                link_down_for: 50ms
            """)
        s = C.expand(c)
        on = [x for x in s if "cut" in x.faults]
        self.assertTrue(30 < len(on) < 90, len(on))
        ats = [iec_time.parse(x.faults["cut"]["link_down_at"]) for x in on]
        self.assertTrue(all(10 * 10**9 <= t <= 60 * 10**9 for t in ats))
        self.assertTrue(all(t % 10**6 == 0 for t in ats))  # whole milliseconds
        self.assertGreater(len(set(ats)), len(ats) // 2)

    def test_a_factor_needs_a_number_in_the_base(self):
        d = Dir()
        with self.assertRaises(CampaignError) as e:
            C.load(d.campaign("faults:\n  - {name: f, device: dev, params: {tau: {factor: 2}}}\n"))
        self.assertIn("a factor needs a number at 'devices.dev.params.tau'", str(e.exception))
        self.assertEqual(e.exception.line, 4)


class Overrides(unittest.TestCase):
    def test_a_path_missing_from_the_base_names_the_campaign_line(self):
        d = Dir()
        with self.assertRaises(CampaignError) as e:
            C.load(d.campaign("parameters:\n  - path: devices.scale.params.noise\n"
                              "    values: [1]\n"))
        self.assertEqual((e.exception.file, e.exception.line, e.exception.column),
                         (os.path.join(d.path, "c.yaml"), 4, 11))
        self.assertIn("no item named 'scale' in 'devices'", e.exception.message)
        with self.assertRaises(CampaignError) as e:
            C.load(d.campaign("parameters:\n  - path: tasks.main.perod\n    values: [1ms]\n"))
        self.assertIn("has no 'tasks.main.perod'", e.exception.message)
        with self.assertRaises(CampaignError) as e:
            C.load(d.campaign("parameters:\n  - path: programs.P.bind.x\n    values: [1]\n"))
        self.assertIn("has no 'programs.P.bind'", e.exception.message)

    def test_init_and_params_keys_may_be_new_and_the_rest_is_kept(self):
        _, c = load("""\
            parameters:
              - path: programs.P.init.target
                values: [7]
              - path: devices.dev.params.initial
                values: [0.5]
            """)
        s = C.expand(c)[0]
        self.assertIn("init:\n    target: 7", s.config_text)
        self.assertIn("initial: 0.5", s.config_text)
        self.assertIn("tau: 2s", s.config_text)

    def test_scenario_configs_run_from_anywhere(self):
        d = Dir()
        with open(os.path.join(d.path, "cell.yaml"), "w") as f:
            f.write(BASE.replace("  - name: sim\n", "  - name: sim\n    params: {gsdml: dev.xml, "
                                 "other: not_a_file.xml}\n"))
        with open(os.path.join(d.path, "dev.xml"), "w") as f:
            f.write("<x/>")
        c = C.load(d.campaign("parameters: []\n"))
        s = C.expand(c)[0]
        self.assertIn(os.path.join(d.path, "lib/libcell.so"), s.config_text)
        self.assertIn("gsdml: %s" % os.path.join(d.path, "dev.xml"), s.config_text)
        self.assertIn("other: not_a_file.xml", s.config_text)
        self.assertNotIn("retain:", s.config_text)
        self.assertNotIn("hmi:", s.config_text)

    def test_unknown_campaign_key(self):
        d = Dir()
        with self.assertRaises(CampaignError) as e:
            C.load(d.campaign("paramters: []\n"))
        self.assertEqual(e.exception.line, 3)
        self.assertIn("unknown key 'paramters'", e.exception.message)


class Hash(unittest.TestCase):
    def test_hash_is_stable_and_ignores_formatting(self):
        d, c = load("parameters:\n  - path: devices.dev.params.gain\n    values: [2]\n")
        h = C.expand(c)[0].hash
        # Pinned: a change of the hash's recipe makes every results folder
        # rerun everything, so it must be deliberate.
        self.assertEqual(h, C.expand(C.load(os.path.join(d.path, "c.yaml")))[0].hash)
        with open(os.path.join(d.path, "cell.yaml"), "w") as f:
            f.write("# a comment\n" + BASE.replace("{tau: 2s, gain: 1.5}",
                                                    "\n          tau: 2s\n          gain: 1.5"))
        self.assertEqual(C.expand(C.load(os.path.join(d.path, "c.yaml")))[0].hash, h)
        with open(os.path.join(d.path, "cell.yaml"), "w") as f:
            f.write(BASE.replace("tau: 2s", "tau: 3s"))
        self.assertNotEqual(C.expand(C.load(os.path.join(d.path, "c.yaml")))[0].hash, h)

    def test_duration_and_checks_are_part_of_the_hash(self):
        d, c = load("parameters: []\n")
        h = C.expand(c)[0].hash
        c.duration_ns *= 2
        self.assertNotEqual(C.expand(c)[0].hash, h)
        _, c2 = load("parameters: []\n", CHECKS.replace("P.x = 0", "P.x = 1"))
        self.assertNotEqual(C.expand(c2)[0].hash, h)


class IecTime(unittest.TestCase):
    def test_parse_and_format_as_plcrun(self):
        self.assertEqual(iec_time.parse("T#1m30s"), 90 * 10**9)
        self.assertEqual(iec_time.parse("10m"), 600 * 10**9)
        self.assertEqual(iec_time.parse("1.5s"), 1500 * 10**6)
        self.assertEqual(iec_time.parse("250ms"), 250 * 10**6)
        self.assertIsNone(iec_time.parse("10min"))
        self.assertIsNone(iec_time.parse("abc"))
        self.assertEqual(iec_time.format_ns(1500 * 10**6), "1500ms")
        self.assertEqual(iec_time.format_ns(2 * 10**9), "2s")


if __name__ == "__main__":
    unittest.main()
