"""``ednc serve`` names every address it opens in its first line (issue 25: it logged only
the HTTP port), and never a database password."""

from __future__ import annotations

from server.settings import load_settings


def test_the_first_line_names_http_machines_mqtt_and_the_database() -> None:
    from ednc.commands.serve import ports_line

    settings = load_settings(None, http_host="127.0.0.1", http_port=8081,
                             machine_host="127.0.0.1", machine_port=7879,
                             mqtt_host="127.0.0.1", mqtt_port=1884,
                             database_url="postgresql+psycopg://ednc:s3cret@127.0.0.1:5432/ednc")
    line = ports_line(settings)
    assert "HTTP http://127.0.0.1:8081" in line
    assert "machines TCP 127.0.0.1:7879" in line
    assert "MQTT broker 127.0.0.1:1884" in line
    assert "127.0.0.1:5432/ednc" in line and "s3cret" not in line
