"""Settings: environment, env file, and the start-up messages for bad values."""

from __future__ import annotations

from pathlib import Path

import pytest

from server.settings import Settings, SettingsError, load_settings


@pytest.fixture(autouse=True)
def clean_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    import os

    for key in list(os.environ):
        if key.startswith("EDNC_") and key != "EDNC_REQUIRE_SERVICES":
            monkeypatch.delenv(key)


def test_defaults() -> None:
    s = load_settings()
    assert s.database_url == "sqlite:///./ednc.db"
    assert (s.http_host, s.http_port) == ("127.0.0.1", 8080)
    assert (s.machine_host, s.machine_port) == ("0.0.0.0", 7878)
    assert s.mqtt_host is None and not s.mqtt_enabled
    assert s.mqtt_topic_prefix == "ednc" and s.push_period_s == 60.0
    assert s.api_key is None and not s.writes_enabled
    assert s.node_id  # host-pid, for leases


def test_environment_overrides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("EDNC_HTTP_PORT", "9000")
    monkeypatch.setenv("EDNC_MQTT_HOST", "127.0.0.1")
    monkeypatch.setenv("EDNC_API_KEY", "key-from-env")
    monkeypatch.setenv("EDNC_PUSH_PERIOD_S", "2.5")
    s = load_settings()
    assert s.http_port == 9000 and s.mqtt_enabled and s.push_period_s == 2.5
    assert s.api_key is not None and s.api_key.get_secret_value() == "key-from-env"
    assert "key-from-env" not in repr(s)


def test_env_file_is_read_and_the_environment_wins(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    env = tmp_path / "ednc.env"
    env.write_text("EDNC_MACHINE_PORT=7000\nEDNC_NODE_ID=center-a\nOTHER=1\n")
    monkeypatch.setenv("EDNC_NODE_ID", "center-b")
    s = load_settings(env)
    assert s.machine_port == 7000 and s.node_id == "center-b"


def test_postgresql_url_gets_the_installed_driver() -> None:
    s = Settings(database_url="postgresql://postgres@127.0.0.1:5432/ednc")
    assert s.database_url == "postgresql+psycopg://postgres@127.0.0.1:5432/ednc"
    url = "postgresql+psycopg://u:p@db/x"
    assert Settings(database_url=url).database_url == url


@pytest.mark.parametrize(("variable", "value", "words"), [
    ("EDNC_HTTP_PORT", "70000", "less than or equal to 65535"),
    ("EDNC_MACHINE_PORT", "seven", "integer"),
    ("EDNC_DATABASE_URL", "mysql://x/y", "unsupported database"),
    ("EDNC_DATABASE_URL", "not a url", "not a database URL"),
    ("EDNC_API_KEY", "short", "at least 8"),
    ("EDNC_MQTT_TOPIC_PREFIX", "ednc/#", "'#'"),
    ("EDNC_MQTT_TOPIC_PREFIX", "a//b", "non-empty"),
    ("EDNC_PUSH_PERIOD_S", "0", "greater than 0"),
    ("EDNC_HEARTBEAT_S", "-1", "greater than 0"),
    ("EDNC_NODE_ID", "two words", "letters, digits"),
    ("EDNC_HTTP_HOST", "bad host", "not a host"),
    ("EDNC_EVENT_RETENTION_DAYS", "0", "greater than 0"),
    ("EDNC_TEMPERATURE_MAX_RATE", "0", "greater than 0"),
    ("EDNC_TEMPERATURE_JUMP", "-1", "greater than or equal to 0"),
    ("EDNC_TEMPERATURE_STALE_S", "0", "greater than 0"),
    ("EDNC_TEMPERATURE_STALE_S", "soon", "number"),
])
def test_bad_value_names_the_variable(
    monkeypatch: pytest.MonkeyPatch, variable: str, value: str, words: str
) -> None:
    monkeypatch.setenv(variable, value)
    with pytest.raises(SettingsError) as info:
        load_settings()
    message = str(info.value)
    assert f"{variable}: " in message and words in message
    if variable == "EDNC_API_KEY":
        assert value not in message


def test_every_problem_is_reported_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("EDNC_HTTP_PORT", "-1")
    monkeypatch.setenv("EDNC_HEARTBEAT_S", "never")
    with pytest.raises(SettingsError) as info:
        load_settings()
    assert "EDNC_HTTP_PORT" in str(info.value) and "EDNC_HEARTBEAT_S" in str(info.value)


def test_empty_optional_values_mean_unset(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("EDNC_API_KEY", "")
    monkeypatch.setenv("EDNC_MQTT_HOST", "")
    s = load_settings()
    assert s.api_key is None and s.mqtt_host is None


def test_a_named_env_file_must_exist(tmp_path: Path) -> None:
    with pytest.raises(SettingsError, match="does not exist"):
        load_settings(tmp_path / "missing.env")


def test_leases_are_taken_on_postgresql_only_unless_asked() -> None:
    from server.settings import Settings

    assert not Settings(database_url="sqlite:///./x.db").uses_leases
    assert Settings(database_url="postgresql://postgres@127.0.0.1:5432/ednc").uses_leases
    assert Settings(database_url="sqlite:///./x.db", leases="on").uses_leases
    assert not Settings(database_url="postgresql://postgres@127.0.0.1/e", leases="off").uses_leases


def test_temperature_rate_and_staleness_from_the_environment(
        monkeypatch: pytest.MonkeyPatch) -> None:
    from server.intake import JUMP_ALLOWANCE_K, MAX_RATE_K_PER_S

    s = load_settings()  # the intake's documented defaults
    assert (s.temperature_max_rate, s.temperature_jump, s.temperature_stale_s) == (
        MAX_RATE_K_PER_S, JUMP_ALLOWANCE_K, 60.0)
    monkeypatch.setenv("EDNC_TEMPERATURE_MAX_RATE", "0.05")
    monkeypatch.setenv("EDNC_TEMPERATURE_JUMP", "0.5")
    monkeypatch.setenv("EDNC_TEMPERATURE_STALE_S", "12.5")
    s = load_settings()
    assert (s.temperature_max_rate, s.temperature_jump, s.temperature_stale_s) == (
        0.05, 0.5, 12.5)
