"""The control center service: machine TCP server, REST API, dashboard, MQTT bridge."""
