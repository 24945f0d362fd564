"""The campaign: which levels the game plays, in which order (``levels/campaign.toml``).

The title screen's *Continue*, the level-select screen and the step to the next
level after a goal all follow this list. An entry whose level file is not
shipped (yet) is skipped, so the campaign can name levels before they exist;
a level file not in the campaign still plays with ``across-dimensions play NAME``.

The file is data only::

    [[level]]
    file = "01_first_steps"   # a level in the levels folder, without ".toml"
    title = "First Steps"     # shown on the level-select screen
    teaches = "..."           # optional, one line under the title
    optional = false          # true: the levels after it are open without it (the prologue)
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

from ..core.errors import InputError
from ..core.fileio import FileProblem, read_text
from .resources import levels_dir

#: Largest campaign file read, in bytes: the shipped one is about 2 kB.
CAMPAIGN_MAX_BYTES = 256 * 1024
CAMPAIGN_FILE = "campaign.toml"
#: Longest level name in an entry: with ".toml" it stays within the 255 bytes a
#: file name may have on common file systems (ext4, NTFS, APFS).
MAX_STEM_CHARS = 200


class CampaignError(InputError):
    """Every problem found in a campaign file, one per line."""


@dataclass(frozen=True)
class CampaignEntry:
    """One level of the campaign.

    Attributes
    ----------
    stem : str
        The level file's name without ``.toml`` (``"01_first_steps"``): the key of saves.
    title : str
        The name shown to the player.
    teaches : str
        One line on what the level introduces (may be empty).
    path : Path
        The level file.
    optional : bool
        The level after it is open whether or not this one was played (the prologue, which a
        player may skip).
    """

    stem: str
    title: str
    teaches: str
    path: Path
    optional: bool = False


def campaign_path() -> Path:
    """The shipped campaign file."""
    return levels_dir() / CAMPAIGN_FILE


def load_campaign(path: Path | None = None) -> list[CampaignEntry]:
    """The campaign's levels in order, without those whose file does not exist.

    Parameters
    ----------
    path : Path, optional
        The campaign file; level files are looked up beside it. Defaults to
        :func:`campaign_path`.

    Raises
    ------
    CampaignError
        If the file cannot be read or is not valid TOML, or an entry is not a
        table with a ``file`` (a plain name, no folders) and a ``title``; one
        line per problem, naming the file and the entry.
    """
    path = Path(path) if path is not None else campaign_path()
    try:
        data = tomllib.loads(read_text(path, limit=CAMPAIGN_MAX_BYTES, what="campaign"))
    except FileProblem as e:
        raise CampaignError(str(e)) from None
    except (tomllib.TOMLDecodeError, ValueError, RecursionError) as e:
        raise CampaignError(f"{path}: not valid TOML ({e})") from None
    entries = data.get("level", [])
    problems: list[str] = []
    if not isinstance(entries, list):
        raise CampaignError(f"{path}: level = {entries!r}: expected [[level]] tables")
    for key in data:
        if key != "level":
            problems.append(f"{path}: unknown entry {key!r}: expected only [[level]] tables")
    result: list[CampaignEntry] = []
    seen: set[str] = set()
    for i, entry in enumerate(entries):
        where = f"{path}: [[level]] #{i + 1}"
        if not isinstance(entry, dict):
            problems.append(f"{where}: expected a table with file and title, got {entry!r}")
            continue
        stem, title, teaches = entry.get("file"), entry.get("title"), entry.get("teaches", "")
        optional = entry.get("optional", False)
        for key in entry:
            if key not in ("file", "title", "teaches", "optional"):
                problems.append(f"{where}: unknown key {key!r}: expected file, title, teaches and optional")
        if not isinstance(stem, str) or not stem or any(c in stem for c in "/\\\0") or stem.startswith("."):
            expected = f"a level name in {path.parent} such as '01_first_steps'"
            problems.append(f"{where}: file = {stem!r}: expected {expected}")
            continue
        if len(stem.encode("utf-8", "surrogatepass")) > MAX_STEM_CHARS:
            problems.append(
                f"{where}: file = {stem[:24]!r}... ({len(stem)} characters): expected a level name of at most "
                f"{MAX_STEM_CHARS} bytes in UTF-8"
            )
            continue
        if not isinstance(title, str) or not title.strip():
            problems.append(f"{where} ({stem}): title = {title!r}: expected the name shown to the player")
            continue
        if not isinstance(teaches, str):
            problems.append(f"{where} ({stem}): teaches = {teaches!r}: expected one line of text")
            continue
        if not isinstance(optional, bool):
            problems.append(f"{where} ({stem}): optional = {optional!r}: expected true or false")
            continue
        if stem in seen:
            problems.append(f"{where}: file = {stem!r} is already in the campaign; expected each level once")
            continue
        seen.add(stem)
        level = path.parent / f"{stem}.toml"
        try:
            shipped = level.is_file()
        except OSError as e:  # whatever else the file system refuses in a name
            problems.append(f"{where}: file = {stem!r}: cannot look for {level.name} ({e.strerror or e})")
            continue
        if shipped:  # not shipped yet: skipped, so the campaign can name future levels
            result.append(CampaignEntry(stem, title.strip(), teaches.strip(), level, optional))
    if problems:
        raise CampaignError("\n".join(problems))
    return result


def next_in_campaign(campaign: list[CampaignEntry], stem: str) -> CampaignEntry | None:
    """The entry after ``stem``, or None after the last one or when ``stem`` is not in the campaign."""
    stems = [e.stem for e in campaign]
    if stem in stems and stems.index(stem) + 1 < len(stems):
        return campaign[stems.index(stem) + 1]
    return None


def locked_because(campaign: list[CampaignEntry], finished, stem: str) -> str:
    """What a click on the locked level ``stem`` says: the level to finish first to open it
    (``finished``: the stems finished so far); "" when ``stem`` is not in ``campaign``."""
    stems = [e.stem for e in campaign]
    if stem not in stems:
        return ""
    i = stems.index(stem)
    need = [e for e in campaign[:i] if not e.optional and e.stem not in finished] or campaign[max(0, i - 1) : i]
    first = f"finish {need[-1].title} first to open" if need else "it opens after"
    return f"Locked: {first} {campaign[i].title}."
