"""Studies from Python: a sweep file run case by case, its table, its runs and bad input."""

import pytest

import hopperflow as hf
from conftest import TINY_SWEEP


@pytest.fixture(scope="module")
def tiny_study(tmp_path_factory):
    out = tmp_path_factory.mktemp("study") / "tiny"
    return hf.study(str(TINY_SWEEP), out=out, jobs=2, progress=False)


def test_a_study_runs_every_case(tiny_study):
    results = tiny_study.results
    assert sorted(results["outlet_width"]) == [0.018, 0.024, 0.030]
    assert set(tiny_study.cases) == set(results["id"])
    assert tiny_study.outcome["ran"] == 3 and tiny_study.outcome["failed"] == []
    for run in tiny_study.cases.values():
        assert run.summary["discharge_rate"] > 0


def test_a_study_resumes_instead_of_rerunning(tiny_study):
    reports: list[hf.Progress] = []
    again = hf.study(str(TINY_SWEEP), out=tiny_study.path, jobs=1, progress=reports.append)
    assert again.outcome is not None
    assert again.outcome["ran"] == 0 and again.outcome["reused"] == 3
    # The progress callable hears of the cases already done, as one StudyProgress.
    assert reports and all(isinstance(p, hf.StudyProgress) for p in reports)
    last = reports[-1]
    assert isinstance(last, hf.StudyProgress)
    assert (last.done, last.total, last.fraction) == (3, 3, 1.0)
    assert last.message == "3/3 cases; 3 of 3 cases already finished"
    loaded = hf.load_study(tiny_study.path)
    assert list(loaded.results["id"]) == list(tiny_study.results["id"])


def test_study_case_runs_match_a_single_run(tiny_study, tmp_path):
    # A case of a study is the same run as that case alone (with the study's outputs).
    case_id = sorted(tiny_study.cases)[0]
    study_run = tiny_study.cases[case_id]
    alone = hf.run(study_run.case, out=tmp_path / "alone", progress=False, pictures=False)
    assert alone.summary == study_run.summary


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"sweep": "no-such-sweep"}, ValueError, "neither a built-in sweep"),
        ({"replicas": 0}, ValueError, "replicas = 0"),
        ({"jobs": -1}, ValueError, "jobs = -1"),
        ({"case_threads": 0}, ValueError, "threads = 0"),
        ({"overrides": {"geometry.outlet_width": float("nan")}}, hf.CaseError, "outlet_width"),
        ({"overrides": {"geometry.nope": 1}}, hf.CaseError, "unknown key"),
    ],
)
def test_bad_study_arguments(kwargs, error, words, tmp_path):
    args = {"sweep": str(TINY_SWEEP), "out": tmp_path / "s", "progress": False, **kwargs}
    with pytest.raises(error, match=words):
        hf.study(**args)


def test_load_study_of_an_empty_folder(tmp_path):
    with pytest.raises(FileNotFoundError):
        hf.load_study(tmp_path)


def test_builtin_sweeps_are_listed():
    assert "fan2023-quick" in hf.builtin_sweeps()


def test_report_is_built_from_the_saved_results(tiny_study):
    page = tiny_study.report()
    assert page.name == "report.html" and page.is_file()
    # The report fits Beverloo over the three widths and lists each case of the study.
    text = page.read_text()
    assert "Beverloo" in text
    assert all(case_id in text for case_id in tiny_study.cases)


def test_a_study_from_one_bed_matches_single_runs_from_it(tiny_bed, tmp_path):
    from conftest import TINY

    bed = tiny_bed
    study = hf.study(str(TINY_SWEEP), out=tmp_path / "study", jobs=2, progress=False, from_bed=bed)
    assert study.outcome is not None
    assert study.outcome["ran"] == 3 and study.outcome["failed"] == []
    # Each case is the single run of its outlet from the same bed, to the byte.
    for run in study.cases.values():
        case = hf.Case.load(str(TINY))
        case["geometry.outlet_width"] = run.summary["outlet_width"]
        single = hf.run(case, out=tmp_path / f"single-{run.path.name}", progress=False, pictures=False, from_bed=bed)
        assert (run.path / "summary.json").read_bytes() == (single.path / "summary.json").read_bytes()
    with pytest.raises(ValueError, match="replicas = 2"):
        hf.study(str(TINY_SWEEP), out=tmp_path / "twice", replicas=2, progress=False, from_bed=bed)
    assert not (tmp_path / "twice").exists()
