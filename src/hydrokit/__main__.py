from hydrokit.cli.entry import entry

entry()
