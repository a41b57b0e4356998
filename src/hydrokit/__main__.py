from hydrokit.cli.main import main

raise SystemExit(main())
