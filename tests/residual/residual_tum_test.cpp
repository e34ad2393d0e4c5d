int placeholder_tum = 0;
