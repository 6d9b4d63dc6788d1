"""The derivation cache against its user's adversaries (express.io.cache_files, the threat
model of docs/cache.md): links planted at an entry's name or as the folder, special files,
folders of other users or with other writers, entries copied, renamed or re-signed, and
`cache clear` that removes only the cache's own files.

Every case here wrote through a link, blocked, or printed another model's numbers before
the fix (issue 36, item 1)."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from cache_support import entries, rewrite_entry, use_fresh_cache
from express.io import cache, cache_files
from express.numeric import statespace
from express.numeric.statespace import load_vehicle

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "conventional.toml"


@pytest.fixture
def model(tmp_path, monkeypatch) -> Path:
    use_fresh_cache(tmp_path, monkeypatch)
    path = tmp_path / "m.toml"
    path.write_bytes(EXAMPLE.read_bytes())
    return path


def _express(*arguments: str, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "express", *arguments], capture_output=True, text=True,
                          timeout=timeout, env=os.environ.copy())


def _warm_and_derivation_entries() -> list[Path]:
    return entries("vehicle warm") + entries("vehicle")


def test_the_folder_and_the_secret_are_private(model):
    load_vehicle(model)
    folder = cache.cache_directory()
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    assert stat.S_IMODE((folder / ".secret").stat().st_mode) == 0o600
    assert all(stat.S_IMODE(p.stat().st_mode) == 0o600 for p in folder.glob("*.json"))


@pytest.mark.parametrize("which", ["vehicle warm", "vehicle"])
def test_a_link_in_place_of_a_warm_entry_is_replaced_never_written_through(model, which):
    assert _express("eigen", str(model)).returncode == 0
    original = model.read_bytes()
    (entry,) = entries(which)
    entry.unlink()
    entry.symlink_to(model)
    run = _express("eigen", str(model))
    assert run.returncode == 0, run.stderr
    assert "a symbolic link" in run.stderr
    assert model.read_bytes() == original  # the model file is untouched
    assert entry.is_file() and not entry.is_symlink()  # the entry was written anew in its place


def test_a_link_planted_before_the_first_run_is_never_written_through(model, tmp_path):
    victim = tmp_path / "victim.json"
    victim.write_text('{"mine": true}')
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        load_vehicle(model)
    planted = _warm_and_derivation_entries()
    names = [p.name for p in planted]
    for path in planted:
        path.unlink()
        path.symlink_to(victim)  # a predictable key: planted in advance at every name
    run = _express("eigen", str(model))
    assert run.returncode == 0, run.stderr
    assert victim.read_text() == '{"mine": true}'
    assert all(not (cache.cache_directory() / n).is_symlink() for n in names)


@pytest.mark.parametrize("special", ["fifo", "device"])
def test_a_special_file_in_place_of_an_entry_does_not_block(model, special):
    assert _express("eigen", str(model)).returncode == 0
    (entry,) = entries("vehicle warm")
    entry.unlink()
    if special == "fifo":
        os.mkfifo(entry)
    else:
        entry.symlink_to("/dev/zero")
    run = _express("eigen", str(model), timeout=60)
    assert run.returncode == 0, run.stderr
    info = _express("cache", "info", timeout=60)
    assert info.returncode == 0


def test_another_models_entry_under_this_key_is_not_used(model, tmp_path):
    other = tmp_path / "other.toml"
    other.write_text(model.read_text().replace('mc = {', 'mc_unused = 1\nmc = {', 1))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mine = load_vehicle(model)
    (my_entry,) = entries("vehicle")
    from express.numeric import statespace, warm

    statespace._GENERATED.clear()
    warm._READ.clear()
    before = set(cache.cache_directory().glob("*.json"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        load_vehicle(other)
    (their_entry,) = [p for p in set(cache.cache_directory().glob("*.json")) - before if b'"kind":"vehicle"' in p.read_bytes()]
    my_entry.write_bytes(their_entry.read_bytes())  # copied under this model's key, header and all
    statespace._GENERATED.clear()
    warm._READ.clear()
    with pytest.warns(UserWarning, match="damaged or foreign entry"):
        again = load_vehicle(model)
    assert (again.mass == mine.mass).all() and again.dofs == mine.dofs


def test_an_entry_signed_with_another_secret_is_refused(model):
    load_vehicle(model)
    assert entries("vehicle")
    (cache.cache_directory() / ".secret").write_bytes(os.urandom(32))  # the folder of another user, copied
    from express.numeric import statespace, warm

    statespace._GENERATED.clear()
    warm._READ.clear()
    with pytest.warns(UserWarning, match="damaged or foreign entry"):
        load_vehicle(model)


def test_a_doctored_kalker_memo_is_computed_anew_not_blamed_on_the_model(tmp_path, monkeypatch):
    use_fresh_cache(tmp_path, monkeypatch)
    path = tmp_path / "k.toml"
    path.write_bytes((EXAMPLE.parent / "manchester.toml").read_bytes())
    good = load_vehicle(path)
    memos = entries("values")
    assert memos, "the Kalker coefficients are kept"
    for memo in memos:
        rewrite_entry(memo, lambda payload: payload["values"].update({k: float("nan") for k in payload["values"]}))
    for entry in entries("vehicle warm") + entries("vehicle"):
        entry.unlink()  # a full load again: the memo is read
    from express.numeric import statespace, warm

    statespace._GENERATED.clear()
    warm._READ.clear()
    with pytest.warns(UserWarning, match="damaged or foreign entry"):
        again = load_vehicle(path)
    assert (again.damping_creep == good.damping_creep).all()


def test_a_folder_with_other_writers_is_refused_with_one_warning(model):
    load_vehicle(model)
    folder = cache.cache_directory()
    folder.chmod(0o777)
    from express.numeric import statespace, warm

    statespace._GENERATED.clear()
    warm._READ.clear()
    with pytest.warns(UserWarning, match="can be written by other users") as caught:
        load_vehicle(model)
        load_vehicle(model)
    assert len([w for w in caught if "derivation cache" in str(w.message)]) == 1
    assert cache.cache_info().refused is not None


def test_a_folder_of_another_user_is_refused(model, monkeypatch):
    load_vehicle(model)
    monkeypatch.setattr(os, "geteuid", lambda: os.stat(cache.cache_directory()).st_uid + 1)
    folder = cache_files.open_folder(cache.cache_directory(), create=False)
    assert folder.refused == "is owned by another user" and not folder.usable


def test_a_folder_this_user_cannot_read_is_refused_with_one_warning(model, capsys, monkeypatch):
    """Issue 36: an unreadable folder was an internal error (PermissionError); the tests run
    as root, whom permissions do not stop, so ``os.access`` answers as for another user."""
    load_vehicle(model)
    folder = str(cache.cache_directory())
    access = os.access
    monkeypatch.setattr(os, "access", lambda path, mode, **kw: False if str(path) == folder else access(path, mode, **kw))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        statespace._GENERATED.clear()  # as a new process: nothing reused in memory
        load_vehicle(model)
    assert [str(w.message) for w in caught] == [
        f"derivation cache: {folder} cannot be read by this user (permission denied); working without the cache"]
    from express.cli import main
    assert main(["cache", "info"]) == 0
    assert "cannot be read by this user" in capsys.readouterr().out


def test_an_entry_larger_than_the_file_limit_is_neither_parsed_nor_written(model, monkeypatch):
    """Issue 36: a 22 MB entry was parsed on every warm run (38 s); entries are smaller than
    the model files they derive from, so the input file limit bounds them."""
    big = {"name": "big", "data": "x" * 1_500_000}
    cache.write_entry("ab" * 32, big)
    assert cache.read_entry("ab" * 32) == big
    monkeypatch.setenv("EXPRESS_MAX_FILE_MB", "1")
    assert cache.entry_bound() == 1024 * 1024
    with pytest.warns(UserWarning, match=r"ignored the damaged or foreign entry .*\(larger than the bound \(1500\d\d\d bytes\)\)"):
        assert cache.read_entry("ab" * 32) is None
    cache.write_entry("cd" * 32, big)
    assert not (cache.cache_directory() / f"{'cd' * 32}.json").exists()


def test_a_linked_folder_is_refused(model, tmp_path, monkeypatch):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir(mode=0o700)
    (tmp_path / "linked").mkdir()
    (tmp_path / "linked" / "derivations").symlink_to(elsewhere)
    monkeypatch.setenv("EXPRESS_CACHE_DIR", str(tmp_path / "linked"))
    with pytest.warns(UserWarning, match="is a symbolic link"):
        load_vehicle(model)
    assert not list(elsewhere.iterdir())


def test_clear_removes_only_its_own_entries_never_through_a_link(model, tmp_path, monkeypatch):
    load_vehicle(model)
    mine = tmp_path / "mine"
    mine.mkdir()
    kept = [mine / "notes.json", mine / "work.tmp", mine / f"{'a' * 64}.json"]
    for path in kept:
        path.write_text("the user's own file")
    folder = cache.cache_directory()
    (folder / f"{'b' * 64}.json").symlink_to(kept[2])  # a link named as an entry
    (folder / "readme.json").write_text("not an entry's name")
    removed = cache.clear_cache()
    assert removed >= 2
    assert all(path.read_text() == "the user's own file" for path in kept)
    assert (folder / "readme.json").exists() and (folder / f"{'b' * 64}.json").is_symlink()
    # a linked derivations/ folder: nothing is removed through it
    linked = tmp_path / "linked"
    linked.mkdir()
    (linked / "derivations").symlink_to(mine)
    monkeypatch.setenv("EXPRESS_CACHE_DIR", str(linked))
    with pytest.warns(UserWarning, match="is a symbolic link"):
        assert cache.clear_cache() == 0
    assert all(path.read_text() == "the user's own file" for path in kept)


def test_entry_names_with_escape_sequences_are_printed_harmless(model):
    load_vehicle(model)
    (entry,) = entries("vehicle warm")
    rewrite_entry(entry, lambda payload: payload.update(name="evil\x1b]0;owned\x07name"))
    info = _express("cache", "info")
    assert "\x1b" not in info.stdout and "\x07" not in info.stdout and "evil?]0;owned?name" in info.stdout


def test_deeply_nested_json_in_an_entry_is_damaged_not_an_internal_error(model):
    load_vehicle(model)
    (entry,) = entries("vehicle warm")
    key = entry.stem
    body = b"[" * 100_000 + b"]" * 100_000
    secret = (entry.parent / ".secret").read_bytes()
    header = b" ".join((b"EXPRESS-DERIVATION-CACHE", str(cache.FORMAT_VERSION).encode(), key.encode(),
                        cache_files.entry_signature(secret, key, body).encode()))
    entry.write_bytes(header + b"\n" + body)
    with pytest.warns(UserWarning, match="damaged or foreign entry"):
        assert cache.read_entry(key) is None
    info = _express("cache", "info")
    assert info.returncode == 0, info.stderr
    assert json.loads(json.dumps(cache.cache_info().models))  # listed, named "?"
